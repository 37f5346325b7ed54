"""L0's LLM shape Designer: text -> ShapeProgram inside the L0 contract's bounds, judged on its renders by a vision
Critic (one revision round), every attempt recorded; the offline grammar stands in, loudly, when it gives none."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import imageio.v3 as iio
import numpy as np
import trimesh

from cache.dont_store import dont_store
from contracts.agents import RoleConfig
from contracts.errors import InputError
from contracts.evidence import AgentSource, Attempt, EvidenceRecord
from contracts.shape import ShapeProgram
from contracts.shape_design import ShapeBounds, ShapeCriticRequest, ShapeCritique, ShapeDesignRequest
from contracts.stage import StageContract, load_contract
from tasks.agents.backend import RoleReply
from tasks.agents.llm import FATAL_ERRORS, Completion, ask, litellm  # litellm as llm.py configures it (offline)
from tasks.geometry import catalogue, pipeline
from tasks.geometry.backends import concept_fields
from tasks.geometry.canonical import canonicalize
from tasks.geometry.meshing import mesh_program
from tasks.geometry.program_checks import check_program
from tasks.render.views import VIEWS, render_view

# an unreachable server will not answer the next time either: stop asking at once, like a refused credential
FATAL_L0: tuple[type[Exception], ...] = (*FATAL_ERRORS, litellm.APIConnectionError)
ACTION = "build_from_text"
CRITIC_VIEW_PX = 256
Mesher = Callable[[ShapeProgram], tuple[trimesh.Trimesh, bool]]  # program -> (asset-frame mesh, reoriented)


@dataclass
class ShapeDesign:
    """What the LLM Designer made: the accepted program and its mesh (None: fall back), and every attempt."""

    program: ShapeProgram | None
    mesh: trimesh.Trimesh | None
    reoriented: bool
    attempts: list[Attempt]
    warnings: list[str] = field(default_factory=list)
    fallback_reason: str | None = None


def has_vision(model: str | None) -> bool:
    """True when litellm says the model reads images."""
    try:
        return bool(model) and bool(litellm.supports_vision(model=model))
    except Exception:  # unknown provider strings
        return False


def render_pngs(mesh: trimesh.Trimesh, size_px: int = CRITIC_VIEW_PX) -> list[bytes]:
    """PNG bytes of the reference views (tasks.render.views: front, side, top and the three-quarter iso)."""
    return [iio.imwrite("<bytes>", render_view(mesh, view, size_px), extension=".png") for view in VIEWS]


def _metrics(program: ShapeProgram, mesh: trimesh.Trimesh) -> dict[str, float]:
    ext = np.asarray(mesh.extents, dtype=np.float64)
    return {"part_count": float(len(program.parts)), "extent_x_m": float(ext[0]), "extent_y_m": float(ext[1]),
            "extent_z_m": float(ext[2]), "volume_m3": float(mesh.volume)}


def _attempt(iteration: int, proposal: dict[str, Any], source: AgentSource, verdict: str, **kw: Any) -> Attempt:
    return Attempt(stage="L0", iteration=iteration, action=ACTION, proposal=proposal, source=source,
                   verdict=verdict, **kw)


def _critique(text: str, program: ShapeProgram, mesh: trimesh.Trimesh, critic: RoleConfig,
              completion: Completion | None) -> RoleReply[ShapeCritique]:
    """The vision Critic's verdict on the rendered views (its retries cost no budget)."""
    req = ShapeCriticRequest(text=text, program=program, views=list(VIEWS),
                             extents_m=tuple(float(v) for v in mesh.extents))
    accept = ShapeCritique(verdict="accept", rationale="the Critic gave no valid verdict: accepted on the contract "
                           "checks")
    return ask("shape_critic", critic, req, ShapeCritique, lambda c: None,
               lambda: RoleReply(accept, AgentSource(backend="rule")), completion, images=render_pngs(mesh),
               fatal_errors=FATAL_L0, structured=False)


def design_shape(text: str, stated_size: str | None, designer: RoleConfig, critic: RoleConfig | None,
                 mesher: Mesher, contract: StageContract | None = None,
                 completion: Completion | None = None) -> ShapeDesign:
    """Ask for a program within 1 + revision_budget answers (an invalid one is fed back and costs one); a vision
    Critic may ask for one revision; program None when no valid program came (budget spent, model unreachable)."""
    contract = contract or load_contract("L0")
    bounds = ShapeBounds.from_contract(contract)
    model = str(designer.model)
    critic = critic if critic is not None and has_vision(critic.model) else None
    attempts: list[Attempt] = []
    warnings: list[str] = []
    left = 1 + contract.revision_budget
    previous: ShapeProgram | None = None
    feedback: str | None = None
    draft: tuple[ShapeProgram, trimesh.Trimesh, bool, int] | None = None
    meshed: dict[str, tuple[trimesh.Trimesh, bool]] = {}  # the last program check() meshed, this round
    while left > 0:
        req = ShapeDesignRequest(text=text, stated_size=stated_size, bounds=bounds, previous=previous,
                                 critique=feedback, budget_left=left)
        meshed.clear()

        def check(program: ShapeProgram) -> str | None:
            if (problem := check_program(program, bounds)) is not None:
                return problem
            try:
                meshed["last"] = mesher(program)
            except InputError as exc:
                return f"the program cannot be meshed into the object: {exc}"
            return None

        reply = ask("shape_designer", designer, req, ShapeProgram, check,
                    lambda: RoleReply(None, AgentSource(backend="rule")), completion, max_answers=left,
                    fatal_errors=FATAL_L0, structured=False)
        parent = draft[3] if draft else None
        for bad in reply.invalid:
            attempts.append(_attempt(len(attempts), {"answer": bad.text[:4000]},
                                     AgentSource(backend="litellm", model=model, errors=[bad.error]), "rejected",
                                     rejected_before_probe=bad.error, parent_iteration=parent))
        left -= len(reply.invalid)
        if reply.value is None:
            reason = reply.source.fallback_reason or "no valid answer"
            if draft is None:
                return ShapeDesign(None, None, False, attempts, warnings, reason)
            program, mesh, rotated, it = draft  # the revision failed: keep the draft the Critic judged
            attempts[it] = attempts[it].model_copy(update={"verdict": "best_so_far"})
            warnings.append(f"the LLM Designer's revision gave no valid program ({reason}); kept its first draft")
            return ShapeDesign(program, mesh, rotated, attempts, warnings)
        left -= 1
        program, (mesh, rotated) = reply.value, meshed["last"]
        it = len(attempts)
        proposal = {"program": program.model_dump(mode="json")}
        evidence = EvidenceRecord(metrics=_metrics(program, mesh))
        verdict_kw: dict[str, Any] = {}
        if critic is not None:
            crit = _critique(text, program, mesh, critic, completion)
            verdict = crit.value
            assert verdict is not None  # the Critic's fallback accepts
            verdict_kw = {"critique": verdict.feedback() if verdict.verdict == "revise" else verdict.rationale,
                          "critic_source": crit.source}
            if verdict.verdict == "revise" and previous is None and left > 0:
                attempts.append(_attempt(it, proposal, reply.source, "revise", evidence=evidence, diagnosis="geometry",
                                         parent_iteration=parent, **verdict_kw))
                draft, previous, feedback = (program, mesh, rotated, it), program, verdict.feedback()
                continue
            if verdict.verdict == "revise":
                warnings.append(f"the shape Critic ({critic.model}) still asks for changes ({verdict.feedback()}); "
                                "kept: one revision round within the budget")
        attempts.append(_attempt(it, proposal, reply.source, "accepted", evidence=evidence, parent_iteration=parent,
                                 **verdict_kw))
        return ShapeDesign(program, mesh, rotated, attempts, warnings)
    raise AssertionError("unreachable: every path through the loop returns")  # pragma: no cover


def from_text_llm(request: Any, settings: Any) -> tuple[dict[str, np.ndarray], Any]:
    """sources.build_mesh for a text request with an LLM Designer (settings.designer): the model's program, meshed
    and sized like the offline path; the offline grammar's build (with a warning) when the model gives none."""
    offline = catalogue.design_from_text(request.text or "", request.size_hint_m)  # stated size, lexicon concept
    size = offline.size.model_copy(update={"axis_scale": (1.0, 1.0, 1.0)})  # the model reads modifier words itself

    def mesher(program: ShapeProgram) -> tuple[trimesh.Trimesh, bool]:
        mesh = mesh_program(program, settings.marching_cubes_resolution)
        mesh, rotated = canonicalize(mesh, "keep_if_stable", align_xy=False)
        if rotated:
            mesh, _ = canonicalize(mesh, "keep_if_stable", align_xy=True)
        return pipeline.final_size(mesh, size), rotated

    designer: RoleConfig = settings.designer
    design = design_shape(request.text or "", size.stated, designer, settings.critic, mesher)
    if design.program is None:
        return _fallback(request, settings, design, designer)
    assert design.mesh is not None
    program = design.program.model_copy(update={"target_extent_m": tuple(float(v) for v in design.mesh.extents)})
    extra = concept_fields(offline, design.mesh)
    info = pipeline.BuildInfo(
        source="text", name=design.program.name, category=offline.program.category, entry=offline.entry,
        program=program, size=offline.size, modifiers=offline.modifiers, reoriented=design.reoriented,
        notes=[f"shape program written by litellm/{designer.model} ({len(design.attempts)} attempt(s)); the lexicon "
               f"read the object as '{offline.entry}'"]
        + ([] if settings.critic is None or has_vision(settings.critic.model) else
           [f"no Critic: litellm/{settings.critic.model} reads no images; accepted on the contract checks"]),
        warnings=[*offline.warnings, *design.warnings], generator=f"litellm/{designer.model}",
        design_attempts=design.attempts, **extra)
    return pipeline.mesh_to_arrays(design.mesh), info


def _fallback(request: Any, settings: Any, design: ShapeDesign, designer: RoleConfig) -> tuple[dict, Any]:
    """The offline grammar's build, its record saying that (and why) the LLM Designer was not used."""
    dont_store()  # the offline build is not kept under the LLM Designer's key: a later run asks the LLM again
    arrays, info = pipeline.mesh_from_text(request, settings)
    note = (f"the LLM Designer (litellm/{designer.model}) gave no valid shape program "
            f"({design.fallback_reason}); built by the offline grammar instead")
    source = AgentSource(backend="fallback_rule", model=designer.model, retries=len(design.attempts),
                         errors=[a.rejected_before_probe or "" for a in design.attempts],
                         fallback_reason=design.fallback_reason)
    proposal = {"entry": info.entry, "program": info.program.model_dump(mode="json") if info.program else None}
    attempts = [*design.attempts, _attempt(len(design.attempts), proposal, source, "accepted", rationale=note)]
    update: dict[str, Any] = {"warnings": [*info.warnings, *design.warnings, note], "generator": "offline",
                              "design_attempts": attempts}
    concept = getattr(info, "concept", None)
    if concept is not None and hasattr(concept, "fallback_note"):
        joined = "; ".join(n for n in (concept.fallback_note, note) if n)
        update["concept"] = concept.model_copy(update={"fallback_note": joined})
    return arrays, info.model_copy(update=update)
