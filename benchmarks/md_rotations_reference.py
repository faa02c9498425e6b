"""One cemented contact between rigid grains: the lattice, with and without rotations, against
an independent continuum reference.

Two rigid spheres of radius R on the z axis, their surfaces 2 eps R apart on the axis, joined by
cement filling the gap within radius a = alpha R of the axis (the cement body of
``md.cemented_contact``). The lower sphere is held, the upper one is moved along z (normal) or
x (tangential, no rotation); the stiffness is the reaction on it. With the grains rigid only the
cement's representation matters, so this separates the cement lattice (translations only, or
rotating, ``rotations`` of ``md.acoustic_system``) from the grain-cement interface's punch.

Solutions of the same problem:

* **continuum** (:func:`axisymmetric_stiffness`): the exact neck (a cylinder r <= a cut by the
  two spheres) by finite elements on a body-fitted mesh of the (r, z) half-plane: the normal
  load is axisymmetric, the tangential one the first Fourier harmonic in the angle (Wilson 1965,
  AIAA J. 3, 2269; Zienkiewicz & Taylor, *The Finite Element Method*, vol. 1, 5th ed., Sect.
  15.3; the bending load, the upper sphere turned about y through its centre, the first
  harmonic too, the torsion the axisymmetric one in u_theta), biquadratic (9-node) elements on
  the exact geometry, refined in halving steps and
  extrapolated (Richardson) with the observed order. Once for the cement, once for the
  continuum the translations-only lattice tends to at long wavelengths
  (:func:`lattice_continuum`: an isotropic solid with another Poisson coupling plus a penalty
  on rigid rotation), which is that lattice's own limit.
* **lattice** (``md.cemented_contact.lattice_contact_stiffness``'s solve with the grains 10^4
  times stiffer than quartz, held in translation and rotation), translations only and rotating
  (this one also turned about y through its centre, bending, and about the axis, torsion), at
  the default lattice position (cell faces on the contact plane and the axis planes) and, at
  ``--offset-omega``, at ``--offsets`` positions (``lattice_offset``, the origin and a scrambled
  Halton sequence), whose mean is what the contacts of a pack, each at its own offset, see.
* **staircase** (:func:`staircase_stiffness`): the lattice's own cell set at resolution Omega
  taken as a continuum body (each cemented cell a cube of cement, each cell whose centre lies
  inside a sphere a rigid cube, as ``md.voxel.pack_phases`` maps a pack), by 8-node trilinear
  bricks (``md.voxel.element_matrices``) with every cell sub-divided into s^3 bricks,
  s = 1, 2, 4, extrapolated in 1/s.

Output: ``results/md_rotations_reference.csv`` (every member; ratios over the cement's
continuum limit at the same eps).
Run: ``python benchmarks/md_rotations_reference.py [--omega 8 10 12 14 16 20 24 32]
[--eps 0.05 0.1] [--offsets 6] [--offset-omega 8 12 18 27] [--staircase-omega 12 16 24]``
(about 10 minutes on one core).

``--twist`` runs the study of the rotating lattice's torsion instead (the leads of
:data:`TWIST_LEADS`: the grain–cement column's length, ``bond_column`` of
``md.cemented_contact.contact_system``, the cemented cells' radius, ``rim_shift``, and the
interface cells' rotations tied to their grain by :func:`rotation_ties`; and ``--flat-leads`` on
a nearly flat neck, a/R ``--flat-alpha``),
over ``--offsets`` lattice offsets; output ``results/md_rotations_reference_twist.csv``.
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

NAME = "md_rotations_reference"
# The loads of the continuum and their columns: normal and tangential (N/m), bending about the
# upper grain's centre and torsion about the axis (N m/rad).
LOADS = ("normal", "tangential", "bending", "torsion")
KEYS = ("kn", "kt", "kb", "kr")

# ----------------------------------------------------------------------------- continuum
# 1-D quadratic Lagrange functions on [-1, 1] (nodes -1, 0, 1) and their derivatives.


def _q(x):
    return np.stack([0.5 * x * (x - 1.0), 1.0 - x * x, 0.5 * x * (x + 1.0)], axis=-1)


def _dq(x):
    return np.stack([x - 0.5, -2.0 * x, x + 0.5], axis=-1)


def _graded(n, power, two_sided):
    """Element boundaries on [0, 1] (``two_sided``: on [-1, 1]) for ``n`` elements, clustered
    toward 1 (and -1) as (1 - u)^power: nested when n doubles."""
    if two_sided:
        u = np.linspace(-1.0, 1.0, n + 1)
        return np.sign(u) * (1.0 - (1.0 - np.abs(u)) ** power)
    u = np.linspace(0.0, 1.0, n + 1)
    return 1.0 - (1.0 - u) ** power


def _isotropic(shear_modulus, p_modulus):
    """D for the strain (e_rr, e_tt, e_zz, g_rz, g_rt, g_tz), engineering shears."""
    lam = p_modulus - 2.0 * shear_modulus
    D = np.zeros((6, 6))
    D[:3, :3] = lam
    D += shear_modulus * np.diag([2.0, 2.0, 2.0, 1.0, 1.0, 1.0])
    return D


def axisymmetric_stiffness(radius_ratio, thickness_ratio, n, *, shear_modulus, p_modulus,
                           rotation_modulus=0.0, radius=1.0, power=1.5, half_height=None,
                           confined=False, loads=("normal", "tangential")):
    r"""Normal and tangential stiffness of a cement neck between two rigid spheres, by
    finite elements in the (r, z) half-plane.

    The neck is :math:`r \le a`, :math:`|z| \le h(r) = R(1 + \varepsilon) - \sqrt{R^2 - r^2}`
    (``half_height`` replaces :math:`h` by a constant: a cylinder between two rigid plates).
    It is bonded to the spheres (:math:`z = \pm h`), free at :math:`r = a` (``confined``: the
    radial displacement held there, the other components free, and for the tangential load
    the affine simple shear imposed there). The displacement is expanded in the angle
    :math:`\theta` (Wilson 1965; Zienkiewicz & Taylor, vol. 1, 5th ed., Sect. 15.3):
    the normal load is axisymmetric, :math:`u_r = U, u_z = W`; the tangential one (upper
    sphere moved by :math:`\delta` along x) is the first harmonic,
    :math:`u_r = U\cos\theta`, :math:`u_\theta = V\sin\theta`, :math:`u_z = W\cos\theta`, the
    sphere's motion :math:`U = \delta, V = -\delta, W = 0`, with strains

    .. math:: \varepsilon_{rr} = U_{,r}, \quad \varepsilon_{\theta\theta} = (U + nV)/r, \quad
              \varepsilon_{zz} = W_{,z}, \quad \gamma_{rz} = U_{,z} + W_{,r}, \quad
              \gamma_{r\theta} = V_{,r} - (V + nU)/r, \quad
              \gamma_{\theta z} = V_{,z} - nW/r

    (times :math:`\cos` or :math:`\sin n\theta`; n = 1, and n = 0 with V the decoupled
    torsion, held at zero). The energy density is the isotropic
    :math:`\tfrac12\lambda(\mathrm{tr}\,\varepsilon)^2 + G\,\varepsilon:\varepsilon` plus,
    with ``rotation_modulus`` :math:`d`, a penalty on the material rotation
    :math:`d\,\omega_{ij}\omega_{ij} = \tfrac12 d\,|2\boldsymbol\omega|^2` (the long-wave
    energy of the translations-only cement lattice, :func:`lattice_continuum`), with
    :math:`2\omega_r = -nW/r - V_{,z}`, :math:`2\omega_\theta = U_{,z} - W_{,r}`,
    :math:`2\omega_z = V_{,r} + (V + nU)/r`. On the axis the displacement is single-valued:
    :math:`U = 0`
    (n = 0), :math:`V = -U`, :math:`W = 0` (n = 1). The stiffness is
    :math:`k = \mathbf u^T K \mathbf u/\delta^2` (twice the strain energy), with
    :math:`K = c_n \int B^T D B\, r\,dr\,dz`, :math:`c_0 = 2\pi`, :math:`c_1 = \pi`.

    Elements: 9-node biquadratic on the exact geometry, the map
    :math:`(s, t) \mapsto (r, z) = (as, h(as)t)` of the rectangle :math:`[0, 1]\times[-1, 1]`
    (the shape functions are polynomials in s and t), ``n`` x ``n`` elements graded toward the
    rim (:math:`s = 1`) and the spheres (:math:`t = \pm 1`) as :math:`(1 - u)^{power}`,
    4 x 4 Gauss points.

    Parameters
    ----------
    radius_ratio : float
        :math:`\alpha = a/R`, in (0, 1).
    thickness_ratio : float
        :math:`\varepsilon`, half the axial gap over R, ``> 0`` (rigid touching spheres are
        infinitely stiff).
    n : int
        Elements along r and along z, ``>= 1``.
    shear_modulus, p_modulus : float
        The cement's :math:`G_c` and :math:`M_c = K_c + \tfrac43 G_c`, Pa.
    rotation_modulus : float
        :math:`d`, Pa, ``>= 0`` (0: the isotropic cement).
    radius : float
        R, m.
    power : float
        Grading exponent, ``>= 1`` (1: uniform).
    half_height : float, optional
        A constant half-thickness, m (flat rigid plates in place of the spheres).
    confined : bool
        Hold the rim as above (the closed forms of a laterally confined layer).

    Returns
    -------
    (float, float)
        Normal and tangential stiffness, N/m.
    """
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    alpha, eps, R = float(radius_ratio), float(thickness_ratio), float(radius)
    if not 0.0 < alpha < 1.0:
        raise ValueError(f"radius_ratio must lie in (0, 1); got {radius_ratio}")
    if half_height is None and not eps > 0.0:
        raise ValueError(f"thickness_ratio must be > 0 (rigid touching spheres are infinitely "
                         f"stiff); got {thickness_ratio}")
    if int(n) < 1:
        raise ValueError(f"n must be >= 1 element; got {n}")
    if not power >= 1.0:
        raise ValueError(f"power must be >= 1; got {power}")
    if not (shear_modulus > 0 and p_modulus > 4.0 / 3.0 * shear_modulus):
        raise ValueError("need shear_modulus > 0 and p_modulus > 4/3 shear_modulus (Pa)")
    if not rotation_modulus >= 0.0:
        raise ValueError(f"rotation_modulus must be >= 0 Pa; got {rotation_modulus}")
    n = int(n)
    a = alpha * R
    if half_height is None:
        def h(r):
            return R * (1.0 + eps) - np.sqrt(R * R - r * r)

        def dh(r):
            return r / np.sqrt(R * R - r * r)
    else:
        H = float(half_height)

        def h(r):
            return np.full_like(r, H)

        def dh(r):
            return np.zeros_like(r)

    se = _graded(n, power, False)
    te = _graded(n, power, True)
    # nodes: (2n + 1) x (2n + 1), parameter values with mid-nodes at the elements' midpoints
    sn = np.empty(2 * n + 1)
    sn[0::2], sn[1::2] = se, 0.5 * (se[:-1] + se[1:])
    tn = np.empty(2 * n + 1)
    tn[0::2], tn[1::2] = te, 0.5 * (te[:-1] + te[1:])
    ns_nodes = 2 * n + 1
    node = np.arange(ns_nodes * ns_nodes).reshape(ns_nodes, ns_nodes)   # [i_s, i_t]
    gx, gw = np.polynomial.legendre.leggauss(4)
    N1, dN1 = _q(gx), _dq(gx)                                     # (4, 3)
    # element (i, j): nodes 2i..2i+2 along s, 2j..2j+2 along t; local node (p, q) -> 3p + q
    ii, jj = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    ii, jj = ii.ravel(), jj.ravel()
    conn = np.stack([node[2 * ii + p, 2 * jj + q] for p in range(3) for q in range(3)], axis=1)
    s0, s1 = se[ii], se[ii + 1]
    t0, t1 = te[jj], te[jj + 1]
    # Gauss points (g along s, k along t)
    S = s0[:, None, None] + 0.5 * (s1 - s0)[:, None, None] * (gx[None, :, None] + 1.0)
    T = t0[:, None, None] + 0.5 * (t1 - t0)[:, None, None] * (gx[None, None, :] + 1.0)
    S, T = np.broadcast_arrays(S, T)
    r = a * S
    hr = h(r)
    z_s = dh(r) * a * T
    # shape functions (e, g, k, 9) and their s, t derivatives
    Nv = (N1[:, None, :, None] * N1[None, :, None, :]).reshape(4, 4, 9)
    Ns = (dN1[:, None, :, None] * N1[None, :, None, :]).reshape(4, 4, 9)
    Nt = (N1[:, None, :, None] * dN1[None, :, None, :]).reshape(4, 4, 9)
    Ns = Ns[None] * (2.0 / (s1 - s0))[:, None, None, None]
    Nt = Nt[None] * (2.0 / (t1 - t0))[:, None, None, None]
    Nz = Nt / hr[..., None]
    Nr = (Ns - Nz * z_s[..., None]) / a
    Nor = Nv[None] / r[..., None]
    w = (gw[:, None] * gw[None, :])[None] * 0.25 * ((s1 - s0) * (t1 - t0))[:, None, None]
    dV = w * r * a * hr                                            # r dr dz
    D = np.zeros((9, 9))
    D[:6, :6] = _isotropic(shear_modulus, p_modulus)
    D[6:, 6:] = rotation_modulus * np.eye(3)            # d w:w = d |2 omega|^2 / 2
    matrices = {}
    results = []
    for load in loads:
        mode = 0 if load in ("normal", "torsion") else 1
        if mode not in matrices:
            matrices[mode] = _harmonic_matrix(mode, Nv.shape, S.shape, Nr, Nz, Nor, D, dV, conn,
                                              node.size)
        K = matrices[mode]
        ndof = K.shape[0]
        # transformation to the independent unknowns: on the axis V = -U (n = 1)
        axis = node[0, :]
        Tm = sp.identity(ndof, format="lil")
        u = np.zeros(ndof)
        fixed = np.zeros(ndof, bool)
        if load == "normal":
            fixed[3 * axis] = True                                        # U = 0
            fixed[3 * node.ravel() + 1] = True                            # no torsion
        elif load == "torsion":
            fixed[3 * node.ravel()] = fixed[3 * node.ravel() + 2] = True  # torsion only
            fixed[3 * axis + 1] = True                                    # V = 0
        else:
            fixed[3 * axis + 2] = True                                    # W = 0
            Tm[3 * axis + 1, 3 * axis] = -1.0                             # V = -U
            Tm[3 * axis + 1, 3 * axis + 1] = 0.0
            fixed[3 * axis + 1] = True       # V is not an unknown on the axis (follows U)
        bottom, top = node[:, 0], node[:, -1]
        rt = a * sn                                  # the radius of the nodes along s
        for nd, move in ((bottom, 0.0), (top, 1.0)):
            fixed[3 * nd], fixed[3 * nd + 1], fixed[3 * nd + 2] = True, True, True
            if load == "normal":
                u[3 * nd + 2] = move
            elif load == "tangential":
                u[3 * nd], u[3 * nd + 1] = move, -move
            elif load == "torsion":                  # turn by 1 rad about z: u_theta = r
                u[3 * nd + 1] = move * rt
            else:                                    # turn by 1 rad about y through the
                zc = h(rt) - R * (1.0 + eps)         # upper sphere's centre: u_x = z - z_c,
                u[3 * nd], u[3 * nd + 1] = move * zc, -move * zc      # u_z = -x
                u[3 * nd + 2] = -move * rt
        if confined:
            rim = node[-1, 1:-1]
            zr = tn[1:-1] * h(np.full(tn.size - 2, a))
            fixed[3 * rim] = True          # u_r held
            if load == "tangential":       # the affine simple shear u_x = z / (2 h) + 1/2
                fixed[3 * rim + 1] = fixed[3 * rim + 2] = True
                ux = 0.5 + zr / (2.0 * h(np.array([a]))[0])
                u[3 * rim], u[3 * rim + 1] = ux, -ux
        Tm = Tm.tocsr()
        free = np.flatnonzero(~fixed)
        Kt = (Tm.T @ K @ Tm).tocsr()
        # prescribed part: u_full = Tm (u_free + u_fixed); the axis V of a fixed U follows it
        u0 = u.copy()
        if mode == 1:
            u0[3 * axis + 1] = 0.0
        rhs = -(Kt[free] @ u0)
        u0[free] = spla.spsolve(Kt[free][:, free].tocsc(), rhs)
        full = Tm @ u0
        results.append(float(full @ (K @ full)))
    return tuple(results)


def _harmonic_matrix(mode, shape_n, shape_g, Nr, Nz, Nor, D, dV, conn, n_nodes):
    """Stiffness matrix of the Fourier harmonic ``mode`` (0 or 1) of
    :func:`axisymmetric_stiffness`: unknowns (U, V, W) per node, strain and rotation rows
    (e_rr, e_tt, e_zz, g_rz, g_rt, g_tz, 2 w_r, 2 w_t, 2 w_z)."""
    import scipy.sparse as sp

    B = np.zeros(shape_g + (9, 27))
    iU, iV, iW = np.arange(9) * 3, np.arange(9) * 3 + 1, np.arange(9) * 3 + 2
    B[..., 0, iU] = Nr
    B[..., 1, iU] = Nor
    B[..., 2, iW] = Nz
    B[..., 3, iU] = Nz
    B[..., 3, iW] = Nr
    B[..., 1, iV] = mode * Nor
    B[..., 4, iV] = Nr - Nor
    B[..., 4, iU] = -mode * Nor
    B[..., 5, iV] = Nz
    B[..., 5, iW] = -mode * Nor
    B[..., 6, iW] = -mode * Nor                     # 2 omega_r
    B[..., 6, iV] = -Nz
    B[..., 7, iU] = Nz                              # 2 omega_theta
    B[..., 7, iW] = -Nr
    B[..., 8, iV] = Nr + Nor                        # 2 omega_z
    B[..., 8, iU] = mode * Nor
    c = 2.0 * np.pi if mode == 0 else np.pi
    Ke = c * np.einsum("egkia,ij,egkjb,egk->eab", B, D, B, dV, optimize=True)
    dof = (3 * conn[:, :, None] + np.arange(3)[None, None, :]).reshape(-1, 27)
    rows = np.repeat(dof, 27, axis=1).ravel()
    cols = np.tile(dof, (1, 27)).ravel()
    ndof = 3 * n_nodes
    return sp.coo_matrix((Ke.ravel(), (rows, cols)), shape=(ndof, ndof)).tocsr()


def lattice_continuum(cement, rotations):
    r"""The continuum the cement lattice tends to at long wavelengths (``md.cement.
    lattice_constants``, ``rule="waves"``): ``(shear_modulus, p_modulus, rotation_modulus)``,
    Pa, for :func:`axisymmetric_stiffness`.

    Summing the energy of the 9 bonds per cell of García & Medina's eq. 6 for a uniform
    displacement gradient :math:`F` (central term :math:`C_n(\hat x\cdot F\hat x)^2|x|^2`,
    tangential term :math:`C|F\hat x|^2`, over the 3 face and 6 edge bonds whose
    :math:`\sum\hat x\hat x^T = 3I`) gives, with the rotating lattice's constants
    (:math:`C_n = \lambda_c c_w`, :math:`C = \tfrac23(G_c - \lambda_c)c_w^3`, the tangential
    term on the strain only), the isotropic cement :math:`(\lambda_c, G_c)`; with the
    translations-only constants (:math:`C_n = \tfrac12(M_c - G_c)c_w`,
    :math:`C = \tfrac16(3G_c - M_c)c_w^3`, on the whole gradient) an isotropic solid with
    :math:`\lambda' = (\lambda_c + G_c)/2`, :math:`G' = (\lambda_c + 3G_c)/4` (so
    :math:`M' = M_c`) plus the rotation penalty :math:`d\,\omega:\omega` with
    :math:`d = 3C/2c_w^3 = (G_c - \lambda_c)/4`; its simple-shear modulus
    :math:`G' + d = G_c`, as calibrated, but a rigid rotation costs energy.
    (Derived here; ``tests/md/test_rotations_reference.py`` checks it against the bond sums.)
    """
    G, M = cement.shear_modulus, cement.p_modulus
    lam = M - 2.0 * G
    if rotations:
        return G, M, 0.0
    return 0.25 * (lam + 3.0 * G), M, 0.25 * (G - lam)


def richardson(h, y):
    """Observed order and limit of the last three members of a sequence ``y(h)`` refined by a
    constant ratio (Roache 1998, *Verification and Validation in Computational Science*, eqs.
    5.4.1-5.4.3): :math:`p = \\ln((y_1 - y_2)/(y_2 - y_3))/\\ln r`, limit
    :math:`y_3 + (y_3 - y_2)/(r^p - 1)`, and the error estimate :math:`|y_3 - y_2|/(r^p - 1)`.
    With a non-monotone sequence (the differences change sign) or one whose changes do not
    shrink, the order is undefined: the limit is the last value and its error the last
    change."""
    h, y = np.asarray(h, float)[-3:], np.asarray(y, float)[-3:]
    if y.size < 3:
        return math.nan, float(y[-1]), float(abs(y[-1] - y[0]))
    ratio = h[0] / h[1]
    d1, d2 = y[0] - y[1], y[1] - y[2]
    if d1 * d2 <= 0 or abs(d2) >= abs(d1) or not np.isclose(h[1] / h[2], ratio):
        return math.nan, float(y[2]), float(abs(d2))
    p = math.log(d1 / d2) / math.log(ratio)
    err = abs(d2) / (ratio**p - 1.0)
    return p, float(y[2] - d2 / (ratio**p - 1.0)), float(err)


# ----------------------------------------------------------------------------- staircase
def staircase_cells(radius_ratio, resolution, thickness_ratio):
    """The lattice's cell set of the contact (``md.cemented_contact``): the phase of every cell
    of its grid, 0 lower grain, 1 upper grain (centre inside that sphere), 2 cement (the cells
    the lattice cements), -1 empty; shape ``(nx, ny, nz)``, x fastest in the flat order."""
    from md.cemented_contact import _cemented_cells

    alpha, eps, omega = float(radius_ratio), float(thickness_ratio), float(resolution)
    _, flat, shape = _cemented_cells(alpha, omega, eps)
    cw = 1.0 / omega
    nx, ny, nz = shape
    half_xy, half_z = nx // 2, nz // 2
    i, j, k = np.meshgrid(np.arange(nx), np.arange(ny), np.arange(nz), indexing="ij")
    centre = np.stack([(i - half_xy + 0.5) * cw, (j - half_xy + 0.5) * cw,
                       (k - half_z + 0.5) * cw], axis=-1)
    phase = np.full(shape, -1, np.int8)
    for g, zg in enumerate((-(1.0 + eps), 1.0 + eps)):
        inside = np.sum((centre - [0.0, 0.0, zg]) ** 2, axis=-1) < 1.0
        phase[inside] = g
    cem = np.zeros(nx * ny * nz, bool)
    cem[flat] = True
    # _cemented_cells numbers the cells i + nx (j + ny k)
    phase[cem.reshape((nz, ny, nx)).transpose(2, 1, 0)] = 2
    return phase


def staircase_stiffness(radius_ratio, resolution, thickness_ratio, subdivision, *,
                        shear_modulus, p_modulus, radius=1.0, rtol=1e-10):
    """Normal and tangential stiffness of the staircase body of :func:`staircase_cells` (the
    cement cells as cubes of cement, the grain cells as rigid cubes moving with their grain)
    by 8-node trilinear bricks (``md.voxel.element_matrices``; Hughes 2000, Chs. 2-3), each
    cell divided into ``subdivision``^3 bricks; solved by conjugate gradients preconditioned
    by smoothed-aggregation multigrid (pyamg). The stiffness is twice the strain energy at a
    unit displacement of the upper grain (z: normal, x: tangential), N/m.

    Parameters
    ----------
    radius_ratio, resolution, thickness_ratio
        :math:`\\alpha`, :math:`\\Omega`, :math:`\\varepsilon` as in
        ``md.cemented_contact.lattice_contact_stiffness``.
    subdivision : int
        Bricks per cell edge, ``>= 1``.
    shear_modulus, p_modulus : float
        The cement's, Pa.
    radius : float
        R, m.
    rtol : float
        Relative residual of the conjugate gradients.
    """
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    from md._kernels_voxel import assemble_blocks, element_nodes
    from md.voxel import _preconditioner, element_matrices

    s = int(subdivision)
    if s < 1:
        raise ValueError(f"subdivision must be >= 1; got {subdivision}")
    phase = staircase_cells(radius_ratio, resolution, thickness_ratio)
    if s > 1:
        phase = np.repeat(np.repeat(np.repeat(phase, s, 0), s, 1), s, 2)
    nx, ny, nz = phase.shape
    h = radius / float(resolution) / s
    # nodes on the (nx + 1, ny + 1, nz + 1) grid: cells numbered on a grid one wider, so the
    # periodic numbering of element_nodes never wraps (no cement cell on the grid's edge)
    NX, NY = nx + 1, ny + 1
    idx = np.argwhere(phase == 2)
    elements = (idx[:, 0] + NX * (idx[:, 1] + NY * idx[:, 2])).astype(np.int64)
    nodes = np.empty((elements.size, 8), np.int64)
    element_nodes(elements, NX, NY, nodes)
    n_nodes = NX * NY * (nz + 1)
    grain_of = np.full(n_nodes, -1, np.int64)
    for g in (0, 1):
        gi = np.argwhere(phase == g)
        ge = (gi[:, 0] + NX * (gi[:, 1] + NY * gi[:, 2])).astype(np.int64)
        gn = np.empty((ge.size, 8), np.int64)
        element_nodes(ge, NX, NY, gn)
        grain_of[gn.ravel()] = g
    used = np.zeros(n_nodes, bool)
    used[nodes.ravel()] = True
    if not (np.any(used & (grain_of == 0)) and np.any(used & (grain_of == 1))):
        raise ValueError("the staircase cement does not join the two grains")
    free_nodes = np.flatnonzero(used & (grain_of < 0))
    free = np.full(n_nodes, -1, np.int64)
    free[free_nodes] = np.arange(free_nodes.size)
    mu = float(shear_modulus)
    lam_v = float(p_modulus) - 2.0 * mu
    lam = np.full(elements.size, lam_v)
    mus = np.full(elements.size, mu)
    KL, KM = element_matrices()
    data = np.zeros((free_nodes.size, 27, 3, 3))
    col = np.full((free_nodes.size, 27), -1, np.int64)
    assemble_blocks(nodes, lam, mus, KL, KM, h, free, data, col)
    keep = col >= 0
    indptr = np.concatenate([[0], np.cumsum(keep.sum(axis=1))])
    A = sp.bsr_matrix((data[keep], col[keep], indptr),
                      shape=(3 * free_nodes.size,) * 2).tocsr()
    del data
    coords = np.stack([free_nodes % NX, (free_nodes // NX) % NY, free_nodes // (NX * NY)],
                      axis=1) * h
    M = _preconditioner(A, "amg", coords)
    Ke = h * (lam_v * KL + mu * KM)
    touching = np.any(grain_of[nodes] == 1, axis=1) | np.any(grain_of[nodes] == 0, axis=1)
    out, iters = [], []
    for ax in (2, 0):
        u = np.zeros((n_nodes, 3))
        u[grain_of == 1, ax] = 1.0
        ue = u[nodes[touching]].reshape(-1, 24)
        fe = -(ue @ Ke.T).reshape(-1, 8, 3)
        rhs = np.zeros((free_nodes.size, 3))
        fn = free[nodes[touching]]
        ok = fn >= 0
        np.add.at(rhs, fn[ok], fe[ok])
        count = [0]

        def step(_, count=count):
            count[0] += 1

        x, info = spla.cg(A, rhs.ravel(), rtol=rtol, atol=0.0, M=M, maxiter=5000,
                          callback=step)
        if info != 0:
            raise RuntimeError(f"staircase solve did not reach rtol {rtol:g}")
        u[free_nodes] = x.reshape(-1, 3)
        ue = u[nodes].reshape(-1, 24)
        out.append(float(np.einsum("ea,ab,eb->", ue, Ke, ue)))
        iters.append(count[0])
    return out[0], out[1], {"elements": int(elements.size), "free_dof": int(3 * free_nodes.size),
                            "iterations": iters}


# ----------------------------------------------------------------------------- twist leads
#: The leads of the twist study (``--twist``): the contact_system options of each (the
#: grain–cement column's length, ``bond_column``; the cemented cells' radius, ``rim_shift``)
#: and whether the interface cells' rotations are tied to their grain's (None, "drilling":
#: the component along the bond normal, "all": all three).
TWIST_LEADS = {
    "default": ({}, None),
    "column_volume": ({"bond_column": "volume"}, None),
    "column_distance": ({"bond_column": "distance", "column_floor": 0.1}, None),
    "column_distance_floor0.05": ({"bond_column": "distance", "column_floor": 0.05}, None),
    "column_distance_floor0.2": ({"bond_column": "distance", "column_floor": 0.2}, None),
    "rim_shift_0.15": ({"rim_shift": 0.15}, None),
    "rim_shift_0.3": ({"rim_shift": 0.3}, None),
    "drilling_tied": ({}, "drilling"),
    "rotation_tied": ({}, "all"),
}
#: Stiffness of the study springs that tie a cell's rotation to its grain's, in units of
#: G_c c_w^3 (N m/rad): stiff against the cell's own rotational stiffness (of order
#: G_c c_w^3), so the tie is a constraint to about 10^-3.
TIE_STIFFNESS = 1e3


def rotation_ties(system, which, stiffness):
    r"""Springs :math:`\tfrac12 k\,|P(\boldsymbol\theta_c - \boldsymbol\theta_g)|^2` on every
    grain–cement bond of ``system`` (an :class:`md.AcousticSystem` with rotations), tying the
    cell's rotation to its grain's: ``which="all"`` :math:`P = I`, ``"drilling"``
    :math:`P = \hat n\hat n^T` (the turn about the bond normal only). Returns the sparse
    matrix to add to the stiffness matrix (``extra`` of
    ``md.cemented_contact._grain_reactions``)."""
    import scipy.sparse as sp

    g = np.asarray(system.bond_i, np.int64)
    c = np.asarray(system.bond_j, np.int64)
    nrm = np.asarray(system.bond_normal, float)
    m = g.size
    P = (np.einsum("bi,bj->bij", nrm, nrm) if which == "drilling"
         else np.broadcast_to(np.eye(3), (m, 3, 3)))
    dof = system.dof
    rows, cols, vals = [], [], []
    for a, b, sign in ((g, g, 1.0), (c, c, 1.0), (g, c, -1.0), (c, g, -1.0)):
        for p in range(3):
            for q in range(3):
                rows.append(dof * a + 3 + p)
                cols.append(dof * b + 3 + q)
                vals.append(sign * stiffness * P[:, p, q])
    n = system.n_particles * dof
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(n, n))


def twist_rows(alpha, eps, cement, radius, omegas, rigid, shifts, leads):
    """The rotating lattice with each lead of :data:`TWIST_LEADS` at every Omega and offset."""
    from md.cemented_contact import _grain_reactions, contact_system

    rows = []
    for lead in leads:
        options, tie = TWIST_LEADS[lead]
        for omega in omegas:
            for o, off in enumerate(shifts):
                t0 = time.perf_counter()
                system = contact_system(alpha, omega, radius=radius, thickness_ratio=eps,
                                        material=rigid, cement=cement, rotations=True,
                                        lattice_offset=tuple(off), **options)
                extra = None
                if tie is not None:
                    cw = system.metadata["cell_width"]
                    extra = rotation_ties(system, tie,
                                          TIE_STIFFNESS * cement.shear_modulus * cw**3)
                k = _grain_reactions(system, (2, 0, 4, 5), extra=extra)
                rows.append(dict(kind="twist_lead", lead=lead, alpha=alpha, eps=eps,
                                 omega=omega, rotations="yes", offset=o, offset_x=off[0],
                                 offset_y=off[1], offset_z=off[2], **dict(zip(KEYS, k)),
                                 seconds=time.perf_counter() - t0))
            print(f"{lead} a/R {alpha} eps {eps} Omega {omega:g}: " + " ".join(
                f"{key} {np.mean([r[key] for r in rows[-len(shifts):]]):.6e}" for key in KEYS),
                flush=True)
    return rows


def twist_summary(df):
    """Markdown table of the twist leads: mean +- standard error over the offsets of each
    stiffness over the cement's continuum limit."""
    lines = []
    for (alpha, eps), g in df[df.kind == "twist_lead"].groupby(["alpha", "eps"]):
        lines += [f"\na/R {alpha:g}, eps {eps:g} (mean over offsets +- standard error)", "",
                  "| lead | Omega | offsets | normal | tangential | bending | torsion |",
                  "|---|---:|---:|---|---|---|---|"]
        for (lead, omega), q in g.groupby(["lead", "omega"], sort=False):
            cells = [_mean_se(q, (k,)) if len(q) > 1 else f"{q[f'{k}_ratio'].iloc[0]:.3f}"
                     for k in KEYS]
            lines.append(f"| {lead} | {omega:g} | {len(q)} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def twist_main(args, cement, rigid, radius):
    """``--twist``: the leads at a/R ``--alpha`` and the first ``--eps``, and ``--flat-leads``
    on a nearly flat neck (``--flat-alpha``, the same eps): their continuum references
    and rows, written to ``results/md_rotations_reference_twist.csv``."""
    import pandas as pd

    rows = []
    cases = [(args.alpha, args.twist_omega, list(args.twist_leads))]
    if args.flat_omega:
        cases.append((args.flat_alpha, args.flat_omega, list(args.flat_leads)))
    eps = args.eps[0]
    for alpha, omegas, leads in cases:
        part = [r for r in continuum_rows(alpha, eps, cement, radius, args.twist_levels)
                if r["material"] == "cement"]
        ref = part[-1]
        part += twist_rows(alpha, eps, cement, radius, omegas, rigid, offsets(args.offsets),
                           leads)
        for r in part:
            for key in KEYS:
                r[f"{key}_ratio"] = r[key] / ref[key]
        rows += part
    df = pd.DataFrame(rows)
    attrs = _common.environment_attrs(
        benchmark=NAME + " --twist", cement=f"{args.cement} (Table II)",
        grains="rigid: quartz x 1e4, held (lattice); bonded rigid spheres (continuum)",
        ratios="each stiffness over the cement's continuum limit at its alpha and eps",
        tie_stiffness=f"{TIE_STIFFNESS:g} G_c c_w^3 (drilling_tied, rotation_tied)",
        **_common.md_source_attrs())
    _common.write_csv(df, _common.result_path(NAME, "csv", "twist"), attrs)
    print(twist_summary(df))


# ----------------------------------------------------------------------------- runs
def continuum_rows(alpha, eps, cement, radius, levels):
    """The continuum references' refinement sequences and their Richardson limits: the
    cement (``material="cement"``) and the translations-only lattice's long-wave continuum
    (``"translations_limit"``, :func:`lattice_continuum`)."""
    rows = []
    for material, rotations in (("cement", True), ("translations_limit", False)):
        G, M, d = lattice_continuum(cement, rotations)
        seq = []
        for n in levels:
            t0 = time.perf_counter()
            k = axisymmetric_stiffness(alpha, eps, n, shear_modulus=G, p_modulus=M,
                                       rotation_modulus=d, radius=radius, loads=LOADS)
            seq.append(dict(kind="continuum", material=material, alpha=alpha, eps=eps,
                            elements=n, **dict(zip(KEYS, k)),
                            seconds=time.perf_counter() - t0))
        limit = dict(kind="continuum_limit", material=material, alpha=alpha, eps=eps,
                     elements=np.inf)
        for key in KEYS:
            p, lim, err = richardson([1.0 / r["elements"] for r in seq], [r[key] for r in seq])
            limit.update({key: lim, f"{key}_order": p, f"{key}_error": err})
        print(f"continuum ({material}) a/R {alpha} eps {eps}: "
              + ", ".join(f"n {r['elements']}: {r['kn']:.9e} / {r['kt']:.9e}" for r in seq)
              + f"; limit {limit['kn']:.9e} +- {limit['kn_error']:.1e} (order "
              f"{limit['kn_order']:.2f}) / {limit['kt']:.9e} +- {limit['kt_error']:.1e} (order "
              f"{limit['kt_order']:.2f})", flush=True)
        rows += seq + [limit]
    return rows


def offsets(count, seed=0):
    """``count`` lattice offsets (cells, in [0, 1)^3): the origin first, then a scrambled
    Halton sequence (scipy.stats.qmc)."""
    from scipy.stats import qmc

    if count <= 1:
        return np.zeros((1, 3))
    return np.vstack([np.zeros(3), qmc.Halton(3, scramble=True, seed=seed).random(count - 1)])


def lattice_rows(alpha, eps, cement, radius, omegas, rigid, shifts):
    """Both lattices at every Omega and every lattice offset of ``shifts``."""
    from md.cemented_contact import _grain_reactions, contact_system

    rows = []
    for omega in omegas:
        for rotations in (False, True):
            for o, off in enumerate(shifts):
                t0 = time.perf_counter()
                system = contact_system(alpha, omega, radius=radius, thickness_ratio=eps,
                                        material=rigid, cement=cement, rotations=rotations,
                                        lattice_offset=tuple(off))
                # translations z, x; with rotations also the turns about y and z
                k = _grain_reactions(system, (2, 0, 4, 5) if rotations else (2, 0))
                rows.append(dict(kind="lattice", alpha=alpha, eps=eps, omega=omega,
                                 rotations="yes" if rotations else "no", offset=o,
                                 offset_x=off[0], offset_y=off[1], offset_z=off[2],
                                 **dict(zip(KEYS, k)), seconds=time.perf_counter() - t0))
                print(f"lattice a/R {alpha} eps {eps} Omega {omega:3g} rot {rotations:d} offset "
                      f"{o}: " + " ".join(f"{key} {v:.6e}" for key, v in zip(KEYS, k))
                      + f" ({rows[-1]['seconds']:.1f} s)", flush=True)
    return rows


def staircase_rows(alpha, eps, cement, radius, omegas, subdivisions):
    """The staircase body at every Omega, sub-divided, and its Richardson limit in 1/s."""
    rows = []
    for omega in omegas:
        seq = []
        for s in subdivisions:
            t0 = time.perf_counter()
            kn, kt, meta = staircase_stiffness(alpha, omega, eps, s,
                                               shear_modulus=cement.shear_modulus,
                                               p_modulus=cement.p_modulus, radius=radius)
            seq.append(dict(kind="staircase", alpha=alpha, eps=eps, omega=omega,
                            subdivision=s, kn=kn, kt=kt, elements=meta["elements"],
                            seconds=time.perf_counter() - t0))
            print(f"staircase a/R {alpha} eps {eps} Omega {omega:3g} s {s}: kn {kn:.6e} kt "
                  f"{kt:.6e} ({meta['elements']} bricks, {seq[-1]['seconds']:.1f} s)",
                  flush=True)
        limit = dict(kind="staircase_limit", alpha=alpha, eps=eps, omega=omega,
                     subdivision=np.inf)
        for key in ("kn", "kt"):
            p, lim, err = richardson([1.0 / r["subdivision"] for r in seq],
                                     [r[key] for r in seq])
            limit.update({key: lim, f"{key}_order": p, f"{key}_error": err})
        rows += seq + [limit]
    return rows


def _fmt(r, key):
    return f"{r[key]:.3f}"


def _mean_se(q, keys):
    """'mean +- standard error' of the ratios ``keys`` over the rows ``q``, ' / '-joined."""
    cols = [f"{k}_ratio" for k in keys]
    m, se = q[cols].mean(), q[cols].std(ddof=1) / np.sqrt(len(q))
    return " / ".join(f"{m[c]:.3f} +- {se[c]:.3f}" for c in cols)


def summary(df):
    """Markdown tables of the run: every stiffness over the cement's continuum limit."""
    lines = []
    for (alpha, eps), g in df.groupby(["alpha", "eps"]):
        ref = g[(g.kind == "continuum_limit") & (g.material == "cement")].iloc[0]
        tl = g[(g.kind == "continuum_limit") & (g.material == "translations_limit")].iloc[0]
        lines += [f"\na/R {alpha:g}, eps {eps:g}: continuum {ref.kn:.6e} +- {ref.kn_error:.0e} "
                  f"/ {ref.kt:.6e} +- {ref.kt_error:.0e} N/m; the translations-only lattice's "
                  f"limit {tl.kn / ref.kn:.4f} / {tl.kt / ref.kt:.4f} of it",
                  "", "| Omega | translations only | rotating | rotating / translations | "
                  "rotating: bending / torsion | staircase (s -> inf) |",
                  "|---:|---|---|---|---|---|"]
        lat = g[(g.kind == "lattice") & (g.offset == 0)]
        st = g[g.kind == "staircase_limit"].set_index("omega")
        for omega, o in lat.groupby("omega"):
            t, r = o[o.rotations == "no"].iloc[0], o[o.rotations == "yes"].iloc[0]
            stc = (f"{st.loc[omega, 'kn_ratio']:.3f} / {st.loc[omega, 'kt_ratio']:.3f}"
                   if omega in st.index else "–")
            lines.append(f"| {omega:g} | {t.kn_ratio:.3f} / {t.kt_ratio:.3f} | "
                         f"{r.kn_ratio:.3f} / {r.kt_ratio:.3f} | {r.kn / t.kn:.4f} / "
                         f"{r.kt / t.kt:.4f} | {r.kb_ratio:.3f} / {r.kr_ratio:.3f} | {stc} |")
        many = g[g.kind == "lattice"].groupby(["omega", "rotations"])
        if many.offset.nunique().max() > 1:
            lines += ["", "mean over lattice offsets (+- standard error of the mean):", "",
                      "| Omega | offsets | translations only | rotating | rotating: bending / "
                      "torsion |", "|---:|---:|---|---|---|"]
            for omega, o in g[g.kind == "lattice"].groupby("omega"):
                if o.offset.nunique() < 2:
                    continue
                cell = {}
                for rot, q in o.groupby("rotations"):
                    cell[rot] = _mean_se(q, ("kn", "kt"))
                cell["turns"] = _mean_se(o[o.rotations == "yes"], ("kb", "kr"))
                lines.append(f"| {omega:g} | {o.offset.nunique()} | {cell['no']} | "
                             f"{cell['yes']} | {cell['turns']} |")
    return "\n".join(lines)


def main(argv=None):
    import pandas as pd

    import md
    from md.contact import QUARTZ, GrainMaterial

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--omega", type=float, nargs="+", default=[8, 10, 12, 14, 16, 20, 24, 32])
    ap.add_argument("--alpha", type=float, default=0.5)
    ap.add_argument("--eps", type=float, nargs="+", default=[0.05, 0.1])
    ap.add_argument("--cement", choices=["hard", "soft"], default="hard")
    ap.add_argument("--levels", type=int, nargs="+", default=[4, 8, 16, 32, 64],
                    help="continuum elements per side, halving steps")
    ap.add_argument("--offsets", type=int, default=6,
                    help="lattice offsets (the origin and a Halton sequence) at --offset-omega")
    ap.add_argument("--offset-omega", type=float, nargs="*", default=[8, 12, 18, 27])
    ap.add_argument("--staircase-omega", type=float, nargs="*", default=[12, 16, 24],
                    help="staircase bodies, at the first --eps only")
    ap.add_argument("--subdivisions", type=int, nargs="+", default=[1, 2, 4])
    ap.add_argument("--twist", action="store_true",
                    help="the twist study instead: the leads of --twist-leads at "
                         "--twist-omega (first --eps), and the default lattice on a nearly "
                         "flat neck (--flat-alpha) at --flat-omega (--flat-leads), over "
                         "--offsets offsets")
    ap.add_argument("--twist-leads", nargs="+", choices=list(TWIST_LEADS),
                    default=list(TWIST_LEADS))
    ap.add_argument("--twist-omega", type=float, nargs="+", default=[8, 12, 16, 24])
    ap.add_argument("--twist-levels", type=int, nargs="+", default=[4, 8, 16, 32],
                    help="continuum elements per side for --twist")
    ap.add_argument("--flat-alpha", type=float, default=0.1)
    ap.add_argument("--flat-omega", type=float, nargs="*", default=[60, 90])
    ap.add_argument("--flat-leads", nargs="+", choices=list(TWIST_LEADS),
                    default=["default", "rim_shift_0.15", "rim_shift_0.3"])
    args = ap.parse_args(argv)
    src = _common.announce_source()
    cement = md.HARD_CEMENT if args.cement == "hard" else md.SOFT_CEMENT
    rigid = GrainMaterial(QUARTZ.shear_modulus * 1e4, QUARTZ.poisson_ratio, QUARTZ.density)
    radius = 1e-4
    if args.twist:
        twist_main(args, cement, rigid, radius)
        print(f"\ncommit {src['git_commit'][:10]}")
        return
    rows = []
    for i, eps in enumerate(args.eps):
        part = continuum_rows(args.alpha, eps, cement, radius, args.levels)
        ref = next(r for r in part if r["kind"] == "continuum_limit"
                   and r["material"] == "cement")
        part += lattice_rows(args.alpha, eps, cement, radius, args.omega, rigid, offsets(1))
        if i == 0 and args.offset_omega:
            part += lattice_rows(args.alpha, eps, cement, radius, args.offset_omega, rigid,
                                 offsets(args.offsets))
        if i == 0 and args.staircase_omega:
            part += staircase_rows(args.alpha, eps, cement, radius, args.staircase_omega,
                                   args.subdivisions)
        for r in part:
            for key in KEYS:
                if key in r:
                    r[f"{key}_ratio"] = r[key] / ref[key]
        rows += part
    df = pd.DataFrame(rows)
    df = df.drop_duplicates(subset=[c for c in ("kind", "material", "eps", "omega",
                                                "rotations", "offset", "subdivision",
                                                "elements") if c in df], keep="first")
    attrs = _common.environment_attrs(
        benchmark=NAME, cement=f"{args.cement} (Table II)", alpha=args.alpha,
        grains="rigid: quartz x 1e4, held (lattice); bonded rigid spheres (continuum, "
               "staircase)",
        ratios="each stiffness over the cement's continuum limit at its eps",
        **_common.md_source_attrs())
    _common.write_csv(df, _common.result_path(NAME, "csv"), attrs)
    print(summary(df))
    print(f"\ncommit {src['git_commit'][:10]}")


if __name__ == "__main__":
    main()
