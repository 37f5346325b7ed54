"""Pack a blind-bench run's views (JPEG, reduced) and rows into one tar, to carry a large run back from another machine.

    python -m benchmarks.pack_views OUT_DIR... --tar views.tar [--width 600]"""

from __future__ import annotations

import argparse
import io
import tarfile
from pathlib import Path

from PIL import Image


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("outs", type=Path, nargs="+")
    ap.add_argument("--tar", type=Path, required=True)
    ap.add_argument("--width", type=int, default=600)
    args = ap.parse_args(argv)
    n = 0
    with tarfile.open(args.tar, "w") as tar:
        for out in args.outs:
            for png in sorted((out / "views").glob("*.png")):
                im = Image.open(png).convert("RGB")
                if im.width > args.width:
                    im = im.resize((args.width, round(im.height * args.width / im.width)), Image.Resampling.LANCZOS)
                buf = io.BytesIO()
                im.save(buf, "JPEG", quality=80)
                info = tarfile.TarInfo(f"views/{png.stem}.jpg")
                info.size = buf.tell()
                buf.seek(0)
                tar.addfile(info, buf)
                n += 1
            for row in sorted((out / "rows").glob("*.json")):
                tar.add(row, arcname=f"rows/{row.name}")
    print(f"{n} views packed into {args.tar}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
