"""The regulation balls' rule drops with a hollow ball built as its shell, or as the solid of before (session 32, issue
#39), measured as session 28 measured them (docs/REALWORLD.md): L0 (draft) and L1's priors of the plain name, a fixed
material (E, nu 0.48, damping 0), its loss calibrated to the ball's own restitution (tasks.realworld.loss.material_loss:
at the 2 m reference speed until session 33, now at the rule's own drop speed), then the rule's drop
(flows.realworld.rule_rebound). One JSON line per ball.
With --gas (session 33), a pressurised ball's shell is simulated at the wall modulus of its gas, E + dE_gas
(tasks.realworld.inflation, from the pressure geometry.json records), as L2 does; a ball with no pressure at E.

    python -m benchmarks.shell_rule_drops "tennis ball" racquetball "padel ball" [--solid] [--gas]
        [--youngs-modulus-pa E]
"""

from __future__ import annotations

import argparse
import json
import shutil
import tempfile
import time
from pathlib import Path

import cache
from contracts.material import Material
from contracts.realworld import load_realworld
from contracts.request import AssetRequest
from contracts.sim import SimConfig
from flows import l0_geometry
from flows.realworld import rule_rebound
from tasks.agents.intent import asset_material, asset_targets, concept_of
from tasks.geometry.outputs import load_l0
from tasks.physical.plan import physical_for
from tasks.realworld.inflation import shell_inflation
from tasks.realworld.loss import material_loss


def drop(name: str, work: Path, youngs_modulus_pa: float, sim: SimConfig, solid: bool = False,
         gas: bool = False) -> dict:
    """One ball's rule drop (its L0 built in `work`; as its shell, the L0 contract's opt-in, unless solid; gas: a
    pressurised shell at its wall modulus)."""
    objects = {o.name: o for o in load_realworld().objects}
    obj = objects[name]
    if obj.rebound is None:
        raise SystemExit(f"{name}: no rebound rule in the real-world set")
    t0 = time.perf_counter()
    request = AssetRequest(text=name, quality="draft")
    l0 = l0_geometry.run_l0(request, quality="draft", use_cache=False,
                            contract=l0_geometry.with_hollow_particles("solid" if solid else "shell"))
    out = work / name.replace(" ", "_")
    shutil.rmtree(out, ignore_errors=True)
    l0_geometry.write_l0(l0, out, request=request)
    asset = load_l0(out)
    physical = physical_for(out, asset)
    base: dict[str, float] = dict(youngs_modulus_pa=youngs_modulus_pa, poisson_ratio=0.48, damping_rate_per_s=0.0)
    inflation = shell_inflation(asset.body, base["poisson_ratio"]) if gas else None
    if inflation:
        base["gas_modulus_pa"] = float(inflation["gas_modulus_pa"])
    targets = asset_targets(asset.record, request)
    fixed, loss = material_loss(asset.particles_m, asset.volumes_m3, physical, Material(**base), targets.priors, sim,
                                concept_of(asset.record), asset_material(asset.record, targets))
    rebound = rule_rebound(obj.rebound, asset, physical, Material(**base, **fixed), sim)
    band = obj.rebound.rebound_ratio
    return {"name": name, "particles_kind": l0.body.kind if l0.body else None,
            "particles_reason": l0.body.reason if l0.body else None, "particles": int(len(asset.particles_m)),
            "spacing_m": asset.spacing_m, "mass_kg": physical.mass_kg, "density_kg_per_m3": physical.density_kg_per_m3,
            "youngs_modulus_pa": youngs_modulus_pa, "gas_modulus_pa": base.get("gas_modulus_pa", 0.0),
            "wall_modulus_pa": Material(**base).wall_modulus_pa, "inflation": inflation, "loss": loss, "band": [band.low, band.high],
            **{k: v for k, v in rebound.items() if k != "rebound_sim"}, "wall_s": time.perf_counter() - t0}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("names", nargs="+", help="balls of the real-world set with a rebound rule")
    ap.add_argument("--solid", action="store_true", help="build every ball solid (the default of L0's "
                    "contract; without it the shell is opted into)")
    ap.add_argument("--gas", action="store_true", help="a pressurised ball's shell at its gas's wall modulus "
                    "(E + dE_gas, tasks.realworld.inflation), as L2 simulates it")
    ap.add_argument("--youngs-modulus-pa", type=float, default=1.58e6, help="E of the fixed material [Pa] (1.58 MPa: "
                    "what L2 adopted for the solid tennis ball in sessions 27-28)")
    ap.add_argument("--work", type=Path, default=None, help="where the L0 directories go (default: a temporary one)")
    args = ap.parse_args()
    sim = SimConfig(device="cpu", cpu_threads=1)
    with tempfile.TemporaryDirectory() as tmp, cache.local_runtime():
        work = args.work or Path(tmp)
        for name in args.names:
            print(json.dumps(drop(name, work, args.youngs_modulus_pa, sim, args.solid, args.gas)), flush=True)


if __name__ == "__main__":
    main()
