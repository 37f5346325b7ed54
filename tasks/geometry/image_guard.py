"""Refuse an image whose header declares more pixels than a limit, before anything decodes it (decompression bombs).

The limit is `MAX_IMAGE_PIXELS_DEFAULT` (40 megapixels: a 7300 x 5500 photo passes), overridden by the environment
variable `DEFORMSMITH_MAX_IMAGE_PIXELS` (a positive integer, pixels). Pillow's own bomb guard
(`PIL.Image.MAX_IMAGE_PIXELS`) is set to the same limit, so Pillow refuses the same images wherever it opens them.
"""

from __future__ import annotations

import os
import warnings
from pathlib import Path

from contracts.errors import InputError

MAX_IMAGE_PIXELS_DEFAULT = 40_000_000  # largest image accepted [px]
ENV_VAR = "DEFORMSMITH_MAX_IMAGE_PIXELS"


def max_image_pixels() -> int:
    """The pixel limit in force: DEFORMSMITH_MAX_IMAGE_PIXELS when set (InputError when not a positive integer)."""
    raw = os.environ.get(ENV_VAR, "").strip()
    if not raw:
        return MAX_IMAGE_PIXELS_DEFAULT
    try:
        value = int(float(raw))
    except ValueError:
        raise InputError(f"{ENV_VAR}={raw!r} is not a number of pixels") from None
    if value <= 0:
        raise InputError(f"{ENV_VAR}={raw!r} must be a positive number of pixels")
    return value


def check_image_size(path: Path) -> tuple[int, int]:
    """(width, height) [px] read from the image's header without decoding it; InputError above the pixel limit."""
    from PIL import Image

    limit = max_image_pixels()
    Image.MAX_IMAGE_PIXELS = limit  # Pillow's own guard agrees with ours (it warns above 1x, raises above 2x)
    path = Path(path)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)
            with Image.open(path) as im:  # reads the header only; pixel data is decoded on .load()
                width, height = im.size
    except Image.DecompressionBombError:
        width, height = _header_size_unchecked(path)
    except (OSError, SyntaxError, ValueError):
        # no image header Pillow knows (every PNG/JPEG has one): refused here, so no decoder sees its size unchecked
        raise InputError(f"cannot read image {path.name}: not a valid PNG/JPEG") from None
    if width * height > limit:
        raise InputError(
            f"image {path.name} is {width} x {height} px ({width * height / 1e6:.0f} MP), more than the "
            f"{limit / 1e6:g} MP allowed (set {ENV_VAR} to raise the limit)")
    return width, height


def _header_size_unchecked(path: Path) -> tuple[int, int]:
    """(width, height) of an image that Pillow refused as a bomb: read again with Pillow's guard off."""
    from PIL import Image

    saved = Image.MAX_IMAGE_PIXELS
    Image.MAX_IMAGE_PIXELS = None
    try:
        with Image.open(path) as im:
            return im.size
    finally:
        Image.MAX_IMAGE_PIXELS = saved
