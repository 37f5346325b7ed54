"""The Planner holds a soft toy or animal by its body: parts from the shape program (or depth), side approaches when
the head is over the torso, and the reason in words."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

from contracts.request import AssetRequest
from contracts.robot import ActionPlan, GraspCandidate
from contracts.shape import ShapeProgram
from tasks.geometry import pipeline, sources
from tasks.robot.grasp import GraspSettings, select_grasps
from tasks.robot.grasp_parts import BODY_PARTS, body_first, body_first_grasps, depth_parts, prefer_body, program_parts
from tasks.robot.trajectory import plan_trajectory

GRIPPER = "robotiq_2f140"


def _grasp(z: float, rank: int) -> GraspCandidate:
    return GraspCandidate(center_m=(0.0, 0.0, z), closing_axis=(1.0, 0.0, 0.0), approach_axis=(0.0, 0.0, -1.0),
                          width_m=0.1, friction_cone_ok=True, score=-float(rank), rank=rank)


@pytest.fixture(scope="module")
def teddy() -> tuple[trimesh.Trimesh, ShapeProgram, str]:
    """A sitting plush teddy bear from text, at draft (its head sits over its torso)."""
    mesh_arrays, info = sources.build_mesh(AssetRequest(text="a plush teddy bear, 30 cm tall"),
                                            pipeline.settings_from_contract("draft"))
    assert info.program is not None and not info.reoriented
    return pipeline.arrays_to_mesh(mesh_arrays), info.program, info.category


def test_prefer_body_puts_body_grasps_first_and_says_why() -> None:
    grasps = [_grasp(0.2, 0), _grasp(0.1, 1), _grasp(0.25, 2)]
    pref = prefer_body(grasps, ["head", "body", "ear"], "the shape program's parts")
    assert [c.center_m[2] for c in pref.candidates] == [0.1, 0.2, 0.25]
    assert [c.rank for c in pref.candidates] == [0, 1, 2]
    assert pref.parts == ["body", "head", "ear"]
    assert "held by the body, not the head" in pref.reason
    none = prefer_body(grasps[:1], ["head"], "depth below the surface")
    assert none.candidates[0].center_m[2] == 0.2 and "no feasible grasp lies on the body" in none.reason


def test_other_categories_keep_the_sampler_order(teddy) -> None:
    mesh, program, _ = teddy
    assert body_first([_grasp(0.2, 0)], "sponge", program, False, mesh) is None
    grasps, why = body_first_grasps(lambda s: [_grasp(0.2, 0)], GraspSettings(gripper=GRIPPER), "kitchen_item",
                                    program, False, mesh)
    assert why == "" and grasps[0].center_m[2] == 0.2


def test_program_parts_name_the_teddy_from_its_feet_to_its_ears(teddy) -> None:
    mesh, program, _ = teddy
    h = float(mesh.extents[2])
    parts = program_parts(np.array([[0.0, 0.0, 0.3 * h], [0.0, 0.0, 0.75 * h]]), program, np.asarray(mesh.bounds))
    assert parts == ["body", "head"]


def test_depth_tells_a_thin_limb_from_the_torso() -> None:
    """Without a program: a 10 cm ball with a 1.2 cm-thick arm; the arm's middle is 'end', the ball's centre 'body'."""
    ball = trimesh.creation.icosphere(subdivisions=3, radius=0.05)
    arm = trimesh.creation.capsule(height=0.08, radius=0.006)
    arm.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [0, 1, 0]))
    arm.apply_translation([0.09, 0.0, 0.0])
    mesh = trimesh.boolean.union([ball, arm], engine="manifold") if trimesh.boolean.engines_available else None
    if mesh is None:
        pytest.skip("no boolean engine")
    assert depth_parts(np.array([[0.0, 0.0, 0.0], [0.1, 0.0, 0.0]]), mesh) == ["body", "end"]


def test_a_sitting_teddy_is_held_by_its_torso_from_the_side(teddy) -> None:
    """Top-down, every feasible grasp of the sitting teddy is on its head (the head is over the torso); the Planner
    then approaches from the side and holds the torso, with a grasp the Panda can execute."""
    mesh, program, category = teddy
    pts, faces = trimesh.sample.sample_surface_even(mesh, 2000, seed=0)
    nrm = mesh.face_normals[faces]

    def select(s: GraspSettings) -> list[GraspCandidate]:
        return select_grasps(pts, nrm, mesh.center_mass, 0.8, settings=s).candidates

    def reachable(c: GraspCandidate) -> bool:
        try:
            plan_trajectory(ActionPlan(grasp=c, gripper=GRIPPER, squeeze_depth_m=0.0, target_xy_m=(0.12, 0.15)),
                            object_height_m=float(mesh.extents[2]))
            return True
        except Exception:
            return False

    settings = GraspSettings(gripper=GRIPPER, soft_indent_m=0.007)
    top = body_first(select(settings), category, program, False, mesh)
    assert top is not None and not any(p in BODY_PARTS for p in top.parts)
    grasps, why = body_first_grasps(select, settings, category, program, False, mesh, reachable)
    best = grasps[0]
    assert program_parts(np.array([best.center_m]), program, np.asarray(mesh.bounds)) == ["body"]
    assert best.approach_axis[2] > -0.9  # not from above
    assert reachable(best)
    assert why.startswith("held by the body") and "from the side" in why


def test_a_condition_that_turns_a_side_grasp_away_from_the_arm_takes_the_next_reachable_one(teddy) -> None:
    """A side grasp reachable with the teddy facing one way is out of reach once the object is turned 180 deg
    (the hand would come from beyond it): the plan under that condition takes the best-ranked grasp that is not."""
    from types import SimpleNamespace

    from tasks.manipulation.trial import plan_or_error, reachable_plan

    mesh, program, category = teddy
    pts, faces = trimesh.sample.sample_surface_even(mesh, 2000, seed=0)
    sel = select_grasps(pts, mesh.face_normals[faces], mesh.center_mass, 0.8,
                        settings=GraspSettings(gripper=GRIPPER, soft_indent_m=0.007, max_tilt_deg=90.0,
                                               approach_turns_deg=(0.0, -90.0, 90.0)))
    body = SimpleNamespace(height_m=float(mesh.extents[2]))
    side = [c for c in sel.candidates if c.approach_axis[2] > -0.3]
    plans = [ActionPlan(grasp=c, gripper=GRIPPER, squeeze_depth_m=0.0, target_xy_m=(0.12, 0.15),
                        initial_yaw_deg=180.0) for c in side]
    turned_away = next(p for p in plans if plan_or_error(p, body)[0] is None)  # type: ignore[arg-type]
    chosen = reachable_plan(turned_away, sel.candidates, body)  # type: ignore[arg-type]
    assert chosen.grasp.rank != turned_away.grasp.rank
    assert plan_or_error(chosen, body)[0] is not None  # type: ignore[arg-type]
    assert chosen.model_copy(update={"grasp": turned_away.grasp}) == turned_away  # only the grasp changed


@pytest.mark.slow  # a few unreachable IK plans of the real Panda (~15 s each on a loaded CPU); the fast test below
def test_a_turned_away_side_grasp_keeps_its_contacts_approached_from_another_side(teddy) -> None:
    """Under a condition that turns the planned side approach out of the arm's reach, the plan keeps the grasp the
    trials tested (its centre, closing axis and width: the same two contacts) and comes in along another approach,
    turned about the closing axis, that the arm reaches and that clears the object; other grasps only after that."""
    from types import SimpleNamespace

    from tasks.manipulation.trial import plan_or_error, reachable_plan
    from tasks.robot.grasp import _hand_hits, turned_approaches
    from tasks.robot.gripper import gripper

    mesh, program, category = teddy
    pts, faces = trimesh.sample.sample_surface_even(mesh, 2000, seed=0)
    settings = GraspSettings(gripper=GRIPPER, soft_indent_m=0.007, max_tilt_deg=90.0,
                             approach_turns_deg=(0.0, -90.0, 90.0))
    sel = select_grasps(pts, mesh.face_normals[faces], mesh.center_mass, 0.8, settings=settings)
    body = SimpleNamespace(height_m=float(mesh.extents[2]), surface_points_m=np.asarray(pts))
    turned_away = (p for c in sel.candidates if c.approach_axis[2] > -0.3
                   for yaw in (180.0, 135.0, -135.0, 90.0, -90.0)
                   if plan_or_error(p := ActionPlan(grasp=c, gripper=GRIPPER, squeeze_depth_m=0.0,
                                                    target_xy_m=(0.12, 0.15), initial_yaw_deg=yaw),
                                    body)[0] is None)  # type: ignore[arg-type]
    kept = 0
    for plan in turned_away:  # the first side grasp and yaw whose contacts another side reaches
        chosen = reachable_plan(plan, sel.candidates, body, grasp_settings=settings)  # type: ignore[arg-type]
        if chosen.grasp.center_m != plan.grasp.center_m:
            continue  # no other side reaches these contacts: another grasp (the test above)
        kept += 1
        g, g0 = chosen.grasp, plan.grasp
        assert plan_or_error(chosen, body)[0] is not None  # type: ignore[arg-type]
        assert (g.center_m, g.closing_axis, g.width_m, g.rank) == (g0.center_m, g0.closing_axis, g0.width_m, g0.rank)
        a, u = np.asarray(g.approach_axis), np.asarray(g.closing_axis)
        assert abs(a @ u) < 1e-9 and a[2] <= 1e-6 and not np.allclose(a, g0.approach_axis)
        assert g in turned_approaches(g0, body.surface_points_m, settings)  # clear of the object and the table
        opening = min(gripper(GRIPPER).stroke_m, g.width_m + 2.0 * settings.open_clearance_m)
        assert not _hand_hits(body.surface_points_m, np.asarray(g.center_m), u / np.linalg.norm(u), a, opening,
                              settings, gripper(GRIPPER))
        break
    assert kept >= 1, "no turned-away side grasp of the teddy could be reached from another side"


def test_turned_approaches_are_perpendicular_and_never_from_below() -> None:
    """A 4 cm cube held across x: the turned approaches keep the closing axis and centre, smallest turn first, and
    none comes up from under the table."""
    from tasks.robot.grasp import turned_approaches

    cube = trimesh.creation.box(extents=(0.04, 0.04, 0.04))
    cube.apply_translation((0.0, 0.0, 0.02))
    pts = trimesh.sample.sample_surface_even(cube, 1500, seed=0)[0]
    g = GraspCandidate(center_m=(0.0, 0.0, 0.03), closing_axis=(1.0, 0.0, 0.0), approach_axis=(0.0, 0.0, -1.0),
                       width_m=0.04, friction_cone_ok=True, score=0.0, rank=3)
    out = turned_approaches(g, pts, GraspSettings(gripper=GRIPPER))
    assert out and all(c.center_m == g.center_m and c.closing_axis == g.closing_axis and c.rank == 3 for c in out)
    tilts = [np.degrees(np.arccos(-c.approach_axis[2])) for c in out]
    assert all(t <= 90.0 + 1e-6 for t in tilts) and tilts == sorted(tilts, key=lambda t: round(t, 6))


def test_reachable_plan_tries_the_same_contacts_from_another_side_before_another_grasp(monkeypatch) -> None:
    """The fallback's order, with reachability stubbed (the arm reaches only approaches with a -y component): a
    turned approach of the planned grasp is taken when one reaches, the next grasp only when none does."""
    from types import SimpleNamespace

    from tasks.manipulation import trial as trial_module
    from tasks.manipulation.trial import reachable_plan

    def reaches(plan, body, settings=None):  # noqa: ANN001, ANN202
        return (object() if plan.grasp.approach_axis[1] < -0.3 else None), ""

    monkeypatch.setattr(trial_module, "plan_or_error", reaches)
    post = trimesh.creation.box(extents=(0.04, 0.04, 0.12))  # a 12 cm post held 3 cm under its top
    post.apply_translation((0.0, 0.0, 0.06))
    body = SimpleNamespace(height_m=0.12, surface_points_m=trimesh.sample.sample_surface_even(post, 1500, seed=0)[0])
    side = GraspCandidate(center_m=(0.0, 0.0, 0.09), closing_axis=(1.0, 0.0, 0.0),
                          approach_axis=(0.0, 0.7071067811865476, -0.7071067811865476), width_m=0.04,
                          friction_cone_ok=True, score=0.0, rank=0)
    other = GraspCandidate(center_m=(0.0, 0.0, 0.08), closing_axis=(0.0, 1.0, 0.0),
                           approach_axis=(-0.7071067811865476, -0.7071067811865476, 0.0), width_m=0.04,
                           friction_cone_ok=True, score=-1.0, rank=1)
    plan = ActionPlan(grasp=side, gripper=GRIPPER, squeeze_depth_m=0.0, target_xy_m=(0.12, 0.15))
    settings = GraspSettings(gripper=GRIPPER)
    chosen = reachable_plan(plan, [side, other], body, grasp_settings=settings)  # type: ignore[arg-type]
    g = chosen.grasp
    assert (g.center_m, g.closing_axis, g.rank) == (side.center_m, side.closing_axis, 0)
    assert g.approach_axis[1] < -0.3  # came round to the reachable side, the same two contacts
    assert reachable_plan(plan, [side, other], body).grasp == other  # type: ignore[arg-type]  # without the settings
