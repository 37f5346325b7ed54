"""One line per bench / profile JSON read from stdin (used by gpu_quick.sh)."""

import json
import sys

d = json.load(sys.stdin)
if "kernels" in d:
    print(f"fast={d['fast_cuda']} particles={d['particles']} kernel us/step={d['kernel_us_per_step']:.1f} "
          + " ".join(f"{n}={v['mean_us']:.1f}x{v['launches']}" for n, v in d["kernels"].items()))
else:
    print(f"particles={d['particles']} batch={d['batch']} us/step={d['us_per_step']:.1f} "
          f"p-steps/s={d['particle_steps_per_s']:.3g} finite={d['finite']}")
