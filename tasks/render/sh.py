"""View-dependent colour from real spherical harmonics (degree 1..3) as 3DGS stores them (f_rest_* in gaussians.ply)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

SH_C1 = 0.4886025119029199
SH_C2 = (1.0925484305920792, -1.0925484305920792, 0.31539156525252005, -1.0925484305920792, 0.5462742152960396)
SH_C3 = (-0.5900435899266435, 2.890611442640554, -0.4570457994644658, 0.3731763325901154, -0.4570457994644658,
         1.445305721320277, -0.5900435899266435)
COEFFS_OF_DEGREE = {3: 1, 8: 2, 15: 3}  # higher-order coefficients per channel -> SH degree


def sh_basis(dirs: np.ndarray, k: int) -> np.ndarray:
    """The first k higher-order SH basis values (N, k) at unit directions (N, 3), in 3DGS's order and signs."""
    x, y, z = dirs[:, 0], dirs[:, 1], dirs[:, 2]
    b = [-SH_C1 * y, SH_C1 * z, -SH_C1 * x]
    if k > 3:
        xx, yy, zz = x * x, y * y, z * z
        b += [SH_C2[0] * x * y, SH_C2[1] * y * z, SH_C2[2] * (2.0 * zz - xx - yy), SH_C2[3] * x * z,
              SH_C2[4] * (xx - yy)]
        if k > 8:
            b += [SH_C3[0] * y * (3.0 * xx - yy), SH_C3[1] * x * y * z, SH_C3[2] * y * (4.0 * zz - xx - yy),
                  SH_C3[3] * z * (2.0 * zz - 3.0 * xx - 3.0 * yy), SH_C3[4] * x * (4.0 * zz - xx - yy),
                  SH_C3[5] * z * (xx - yy), SH_C3[6] * x * (xx - 3.0 * yy)]
    return np.stack(b[:k], axis=1)


def view_colors(colors_rgb: np.ndarray, sh_coeffs: np.ndarray, means_m: np.ndarray, eye_m: np.ndarray) -> np.ndarray:
    """Colours (N, 3) seen from eye: the DC colour plus the higher-order terms along the view direction, >= 0."""
    dirs = means_m - eye_m[None, :]
    dirs = dirs / np.maximum(np.linalg.norm(dirs, axis=1, keepdims=True), 1e-12)
    basis = sh_basis(dirs, sh_coeffs.shape[1])
    return np.clip(colors_rgb + np.einsum("nk,nkc->nc", basis, sh_coeffs), 0.0, None)


def read_sh_rest(path: Path) -> np.ndarray | None:
    """The higher-order SH coefficients (N, K, 3) of a 3DGS .ply (its f_rest_*, stored channel-major), or None."""
    from plyfile import PlyData

    v = PlyData.read(str(path))["vertex"]
    names = sorted((p.name for p in v.properties if p.name.startswith("f_rest_")), key=lambda s: int(s[7:]))
    if not names:
        return None
    k = len(names) // 3
    rest = np.stack([np.asarray(v.data[n], np.float64) for n in names], axis=1)  # (N, 3K): R..., G..., B...
    return rest.reshape(len(rest), 3, k).transpose(0, 2, 1).copy()
