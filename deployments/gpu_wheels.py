"""Carry the project's Python packages to the GPU machine, which reaches no package registry (docs/BENCHMARKS.md,
"Running on the GPU machine").

Here (a machine with PyPI), from the repository root:

    python deployments/gpu_wheels.py prepare [--lean] [--extra export] [--keep NAME ...]

resolves pyproject.toml's dependencies and its `test` extra for CPython 3.12 on x86-64 manylinux, downloads the wheels
the device image does not already hold (DEVICE_HAS: numpy, scipy, OpenCV, ... are the image's own), takes the
packages that have no cp312 wheel as sources (pybullet is built there; wn, pure Python with a distutils setup.py that
Python 3.12 cannot run, is built into a wheel here), splits everything into parts that fit one device call beside the
working tree (at most 60 MB each), groups them into carry folders `.gpuwheels/pNN/` (git-ignored) and prints the
device runs to make back to back (/var/tmp survives between calls only while the machine stays warm):

    carry [".gpuwheels/p00"]:  python3 deployments/gpu_wheels.py receive .gpuwheels/p00
    ...
    carry [".gpuwheels/pNN"]:  python3 deployments/gpu_wheels.py receive .gpuwheels/pNN && \
                               python3 deployments/gpu_wheels.py install

Before `prepare` and the calls, `python deployments/gpu_wheels.py park [--keep docs/results/NAME ...]` moves the
big evidence folders (docs/blind/, and every docs/results/ folder but the kept ones: ~40 of the tracked tree's ~55 MB)
into `.gpuparked/` (git-ignored, so it does not travel), which leaves each call ~44 MB for wheels instead of ~10;
`unpark` puts them back (do it before any commit: while parked, git sees them deleted).

`install` (on the device, standard library only) joins the parts, checks their SHA-256, installs every wheel with
`pip install --no-index --no-deps --target /var/tmp/site`, builds pybullet from its sdist there
(`--no-build-isolation`: the image's setuptools and wheel), and runs `pip check` over the result. Then every command
starts with `export PYTHONPATH=/var/tmp/site:.` and runs the project from the source tree:
`python3 -m flows.cli.main generate ...` (the `deformsmith` command).
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
OUT = REPO / ".gpuwheels"
# on the device: where the parts are joined, and where the packages go (PYTHONPATH); /var/tmp by default, the one
# place a device machine keeps between calls; another machine sets DEFORMSMITH_WHEEL_STAGE / DEFORMSMITH_WHEEL_SITE
STAGE = Path(os.environ.get("DEFORMSMITH_WHEEL_STAGE", "/var/tmp/gw"))
SITE = Path(os.environ.get("DEFORMSMITH_WHEEL_SITE", "/var/tmp/site"))
MANIFEST = "manifest.json"

PYTHON = "3.12"
# manylinux tags pip accepts for the device (glibc 2.39, Ubuntu 24.04): pip matches each tag exactly, so list them all
PLATFORMS = ["manylinux1_x86_64", "manylinux2010_x86_64", "manylinux2014_x86_64",
             *(f"manylinux_2_{n}_x86_64" for n in range(5, 40))]
# No cp312 wheel: `build` sdists are built on the device, `wheel` sdists (pure Python) into a wheel here.
SOURCES = {"pybullet": "build", "wn": "wheel"}
# Compiled or large packages the device image holds ("cuda" image, /work/.library/device/KINDS.md), in versions that
# satisfy our requirements (numpy 2.5.2 there; `install` runs `pip check`). A resolved package of this list is not
# carried; every other one is, and shadows the image's copy (PYTHONPATH comes first).
DEVICE_HAS = {
    "numpy", "scipy", "scikit-image", "opencv-python-headless", "matplotlib", "contourpy", "kiwisolver", "fonttools",
    "pillow", "pyarrow", "tifffile", "lazy-loader", "networkx", "pyyaml", "psutil", "regex", "tokenizers",
    "tiktoken", "hf-xet", "huggingface-hub", "setuptools", "pytest", "pluggy", "iniconfig", "execnet",
    "pytest-timeout", "pytest-xdist", "pygments", "markupsafe", "jinja2", "grpcio", "protobuf",
}
# `--lean` leaves these out (and whatever only they need): litellm serves only `--llm`, ruff and mypy only the lint
# tests; about 100 MB, two or three device calls fewer.
LEAN_OUT = {"litellm", "ruff", "mypy"}
MB = 1_000_000
PART_MAX = 60 * MB  # the bound on one part
CALL_MAX = 64 * 1024 * 1024  # what one device call carries: the working tree and the carried folder together
MARGIN = 8 * MB  # files added to the tree between `prepare` and the calls (docs grow ~2 MB a session: contact sheets)


PARKED = ".gpuparked"  # where `park` moves the evidence folders: inside the repo, git-ignored, not carried
PARK_FOLDERS = ("docs/blind",)  # parked whole
PARK_CHILDREN = ("docs/results",)  # each child parked, but those named by --keep


def _exclude(root: Path, entry: str) -> None:
    """Add `entry` to the repository's .git/info/exclude once."""
    exclude = root / ".git" / "info" / "exclude"
    exclude.parent.mkdir(parents=True, exist_ok=True)
    lines = exclude.read_text(encoding="utf-8").splitlines() if exclude.is_file() else []
    if entry not in lines:
        exclude.write_text("\n".join([*lines, entry]) + "\n", encoding="utf-8")


def park(root: Path, keep: list[str]) -> list[str]:
    """Move the evidence folders out of what a device call carries, into root/.gpuparked (their paths kept beneath
    it); the relative paths moved. Refused while something is parked already."""
    parked = root / PARKED
    if parked.exists() and any(parked.iterdir()):
        raise SystemExit(f"{PARKED}/ is not empty: run `unpark` first")
    kept = {Path(k).as_posix().rstrip("/") for k in keep}
    moves = [f for f in PARK_FOLDERS if (root / f).is_dir()]
    for folder in PARK_CHILDREN:
        if (root / folder).is_dir():
            moves += sorted(c.relative_to(root).as_posix() for c in (root / folder).iterdir()
                            if c.relative_to(root).as_posix() not in kept)
    _exclude(root, f"/{PARKED}/")
    for rel in moves:
        (parked / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.move(root / rel, parked / rel)
    return moves


def unpark(root: Path) -> list[str]:
    """Move everything parked back where it was; the relative paths restored. Refused, moving nothing, when one of
    them exists again in the tree."""
    parked = root / PARKED
    if not parked.is_dir():
        return []
    moves = []
    for top in [*PARK_FOLDERS, *PARK_CHILDREN]:
        src = parked / top
        if not src.exists():
            continue
        if top in PARK_FOLDERS:
            moves.append(top)
        else:
            moves += sorted(c.relative_to(parked).as_posix() for c in src.iterdir())
    clash = [m for m in moves if (root / m).exists()]
    if clash:
        raise SystemExit(f"cannot unpark: {clash[0]} exists in the tree again; move it aside first")
    for rel in moves:
        (root / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.move(parked / rel, root / rel)
    shutil.rmtree(parked)
    return moves


def norm(name: str) -> str:
    return re.sub(r"[-_.]+", "-", name).lower()


def pip(*args: str, quiet: bool = True) -> subprocess.CompletedProcess[str]:
    cmd = [sys.executable, "-m", "pip", *args] + (["-q"] if quiet else [])
    return subprocess.run(cmd, check=True, text=True, capture_output=True)


def requirements(extras: list[str]) -> list[str]:
    import tomllib

    project = tomllib.loads((REPO / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    reqs = list(project["dependencies"])
    for extra in extras:
        reqs += project["optional-dependencies"][extra]
    return reqs


def req_name(req: str) -> str:
    return norm(re.split(r"[<>=!~ ;\[]", req, maxsplit=1)[0])


def platform_args() -> list[str]:
    out = ["--only-binary=:all:", "--python-version", PYTHON, "--implementation", "cp"]
    for p in PLATFORMS:
        out += ["--platform", p]
    return out


def resolve(reqs: list[str]) -> dict[str, str]:
    """name -> version of every wheel pip's resolver picks for the device (dependencies included)."""
    with tempfile.TemporaryDirectory() as tmp:
        report = Path(tmp) / "report.json"
        pip("install", "--dry-run", "--ignore-installed", "--target", str(Path(tmp) / "t"), "--report", str(report),
            *platform_args(), *reqs)
        data = json.loads(report.read_text(encoding="utf-8"))
    return {norm(i["metadata"]["name"]): i["metadata"]["version"] for i in data["install"]}


def tree_bytes() -> int:
    """What a device call sends besides its carry: tracked and untracked, not ignored files."""
    out = subprocess.run(["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"], cwd=REPO,
                         check=True, capture_output=True).stdout
    return sum((REPO / p).stat().st_size for p in out.decode().split("\0") if p and (REPO / p).is_file())


def prepare(args: argparse.Namespace) -> None:
    reqs = requirements(["test", *args.extra])
    if args.lean:
        reqs = [r for r in reqs if req_name(r) not in LEAN_OUT]
    wheel_reqs = [r for r in reqs if req_name(r) not in SOURCES]
    source_reqs = [r for r in reqs if req_name(r) in SOURCES]
    print(f"resolving {len(wheel_reqs)} requirements for CPython {PYTHON} x86-64 manylinux ...", file=sys.stderr)
    picked = resolve(wheel_reqs)
    keep = {norm(k) for k in args.keep}
    skipped = {n: v for n, v in picked.items() if n in DEVICE_HAS and n not in keep}
    carried = {n: v for n, v in picked.items() if n not in skipped}
    shutil.rmtree(OUT, ignore_errors=True)
    dl = OUT / "dl"
    dl.mkdir(parents=True)
    print(f"downloading {len(carried)} wheels and {len(source_reqs)} sources ...", file=sys.stderr)
    pip("download", "--no-deps", *platform_args(), "-d", str(dl), *(f"{n}=={v}" for n, v in sorted(carried.items())))
    for r in source_reqs:
        if SOURCES[req_name(r)] == "build":
            pip("download", "--no-deps", "--no-binary=:all:", "-d", str(dl), r)
        else:
            pip("wheel", "--no-deps", "--no-binary=:all:", "-w", str(dl), r)
    if not args.with_rerun_viewer:
        slim_rerun(dl)
    budget = min(PART_MAX, CALL_MAX - tree_bytes() - MARGIN)
    files = {f.name: sha256(f) for f in sorted(dl.iterdir())}
    parts = split(dl, budget)
    folders = pack(parts, budget)
    lock = {"python": PYTHON, "carried": carried, "skipped_device_has": skipped, "sources": source_reqs,
            "files": files, "folders": len(folders)}
    for folder in folders:
        (folder / MANIFEST).write_text(json.dumps(lock, indent=1, sort_keys=True), encoding="utf-8")
    shutil.rmtree(dl)
    total = sum(f.stat().st_size for f in OUT.glob("p*/*"))
    print(f"{len(files)} files, {total / MB:.0f} MB in {len(folders)} carry folders of <= {budget / MB:.1f} MB "
          f"(the working tree travels beside each); left to the device image: {', '.join(sorted(skipped))}")
    print("Device runs, back to back (/var/tmp is lost once the machine goes back after ~30 s idle):")
    for i, folder in enumerate(folders):
        rel = folder.relative_to(REPO)
        cmd = f"python3 deployments/gpu_wheels.py receive {rel}"
        if i == len(folders) - 1:
            cmd += " && python3 deployments/gpu_wheels.py install"
        print(f'  carry ["{rel}"]  command: {cmd}')
    print("Then begin every command with: export PYTHONPATH=/var/tmp/site:.")


def slim_rerun(dl: Path) -> None:
    """rerun-sdk's wheel without its viewer binary (rerun_cli/rerun, ~2/3 of the wheel): needed only by `deformsmith
    view`, never by a headless run; the recording SDK stays."""
    import zipfile

    for whl in dl.glob("rerun_sdk-*.whl"):
        slim = whl.with_suffix(".slim")
        with zipfile.ZipFile(whl) as src, zipfile.ZipFile(slim, "w", zipfile.ZIP_DEFLATED) as dst:
            for item in src.infolist():
                if item.filename.startswith("rerun_cli/rerun") and not item.filename.endswith(".py"):
                    continue
                data = src.read(item)
                if item.filename.endswith(".dist-info/RECORD"):
                    data = b"".join(line for line in data.splitlines(keepends=True)
                                    if not (line.startswith(b"rerun_cli/rerun") and b".py," not in line))
                dst.writestr(item, data)
        slim.replace(whl)


def sha256(path: Path) -> str:
    h = hashlib.sha256()
    with path.open("rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def split(dl: Path, size: int) -> list[Path]:
    """Every file as parts of at most `size` bytes, named FILE.partNN (a small file is one part)."""
    parts = []
    for f in sorted(dl.iterdir()):
        with f.open("rb") as src:
            i = 0
            while block := src.read(size):
                part = dl / f"{f.name}.part{i:02d}"
                part.write_bytes(block)
                parts.append(part)
                i += 1
        f.unlink()
    return parts


def pack(parts: list[Path], budget: int) -> list[Path]:
    """Parts into folders .gpuwheels/pNN of at most `budget` bytes each (first fit, largest first)."""
    bins: list[tuple[int, list[Path]]] = []
    for p in sorted(parts, key=lambda q: -q.stat().st_size):
        s = p.stat().st_size
        for i, (used, members) in enumerate(bins):
            if used + s <= budget:
                bins[i] = (used + s, [*members, p])
                break
        else:
            bins.append((s, [p]))
    folders = []
    for i, (_, members) in enumerate(bins):
        folder = OUT / f"p{i:02d}"
        folder.mkdir()
        for p in members:
            p.rename(folder / p.name)
        folders.append(folder)
    return folders


def receive(args: argparse.Namespace) -> None:
    """On the device: move one carried folder's parts (and the manifest) to /var/tmp/gw."""
    STAGE.mkdir(parents=True, exist_ok=True)
    src = Path(args.folder)
    for f in src.iterdir():
        shutil.move(f, STAGE / f.name)
    have = len(list(STAGE.glob("*.part*")))
    print(f"received {src.name}: {have} parts in {STAGE}")


def install(args: argparse.Namespace) -> None:
    """On the device: join the parts, check them, install the wheels and build the sources into /var/tmp/site."""
    lock = json.loads((STAGE / MANIFEST).read_text(encoding="utf-8"))
    for name, digest in lock["files"].items():
        target = STAGE / name
        if not target.is_file():
            pieces = sorted(STAGE.glob(f"{glob_escape(name)}.part*"))
            with target.open("wb") as out:
                for piece in pieces:
                    out.write(piece.read_bytes())
        if sha256(target) != digest:
            target.unlink()
            sys.exit(f"{name}: missing or damaged parts (was every carry folder received since the machine started?)")
    for piece in STAGE.glob("*.part*"):
        piece.unlink()
    names = sorted(lock["files"])
    base = [sys.executable, "-m", "pip", "install", "-q", "--no-index", "--no-deps", "--no-cache-dir",
            "--disable-pip-version-check", "--upgrade", "--target", str(SITE)]
    wheels = [str(STAGE / n) for n in names if n.endswith(".whl")]
    subprocess.run([*base, "--no-compile", *wheels], check=True)
    sources = [str(STAGE / n) for n in names if not n.endswith(".whl")]
    if sources:  # built against the image's setuptools / wheel; pybullet compiles in about a minute on 16 cores
        subprocess.run([*base, "--no-build-isolation", *sources], check=True)
    # every broken requirement that names one of our packages (the image's own unrelated ones are only counted)
    env = {**os.environ, "PYTHONPATH": str(SITE)}
    check = subprocess.run([sys.executable, "-m", "pip", "check"], env=env, text=True, capture_output=True)
    ours = {norm(n) for n in [*lock["carried"], *lock["skipped_device_has"], *SOURCES]}
    broken = [ln for ln in check.stdout.splitlines() if ln.strip()]
    mine = [ln for ln in broken if ours & {norm(w.strip(",.")) for w in ln.split()}]
    print(f"pip check: {len(mine)} broken requirements name our packages, {len(broken) - len(mine)} others")
    for ln in mine:
        print("  " + ln)
    print(f"installed {len(wheels)} wheels and {len(sources)} sources into {SITE}; "
          f"now: export PYTHONPATH={SITE}:.")


def glob_escape(name: str) -> str:
    return re.sub(r"([*?\[])", r"[\1]", name)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    p = sub.add_parser("prepare", help="here: resolve, download and split into .gpuwheels/pNN")
    p.add_argument("--extra", action="append", default=[], help="another extra of pyproject.toml (e.g. export)")
    p.add_argument("--keep", action="append", default=[], help="carry this package although the device has it")
    p.add_argument("--lean", action="store_true", help=f"leave out {', '.join(sorted(LEAN_OUT))}")
    p.add_argument("--with-rerun-viewer", action="store_true", help="keep rerun-sdk's viewer binary")
    p.set_defaults(fn=prepare)
    r = sub.add_parser("receive", help="device: copy one carried folder to /var/tmp/gw")
    r.add_argument("folder")
    r.set_defaults(fn=receive)
    i = sub.add_parser("install", help="device: join, check and install into /var/tmp/site")
    i.set_defaults(fn=install)
    k = sub.add_parser("park", help="here: move the evidence folders out of what a call carries (.gpuparked/)")
    k.add_argument("--keep", action="append", default=[], help="a docs/results/ folder the device needs (repeatable)")
    k.set_defaults(fn=lambda a: print(f"parked {len(park(REPO, a.keep))} folders in {PARKED}/; "
                                      "`unpark` before any commit"))
    u = sub.add_parser("unpark", help="here: put the parked folders back")
    u.set_defaults(fn=lambda a: print(f"restored {len(unpark(REPO))} folders"))
    args = ap.parse_args()
    args.fn(args)


if __name__ == "__main__":
    main()
