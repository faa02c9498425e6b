"""Synthetic seismograms of a depth profile: two-way time, reflectivity series, Ricker wavelet,
convolution, angle gathers.

A profile is sampled at depths ``depth`` (m, below the datum, strictly increasing along the last
axis) with velocities in km/s and densities in g/cm³ on the same last axis; leading axes (models,
fluids, ...) broadcast. Times are in seconds, frequencies in Hz.

The functions take numpy arrays (and lists); pandas and xarray inputs are refused with a message,
because they work along the depth axis, which :func:`rockcem.validation.labelled` does not know:
give ``da.transpose(..., "depth").values`` or ``series.to_numpy()``.

Sources: the wavelet of [Ricker1953]_ (Ricker, N., 1953. The form and laws of propagation of
seismic wavelets. Geophysics 18, 10-40); the convolutional model of a layered earth, chapter 2 of
[Yilmaz2001]_ (Yilmaz, O., 2001. Seismic Data Analysis, SEG); reflection coefficients from
:mod:`rockcem.reflectivity`.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from scipy.signal import oaconvolve

from .reflectivity import zoeppritz_pp
from .validation import as_array, as_scalar, check_range

__all__ = ["Wavelet", "Synthetic", "AngleGather", "MAX_SAMPLES", "depth_to_twt", "ricker",
           "reflectivity_series", "synthetic_trace", "angle_gather"]

#: Most samples of a time grid or a wavelet (a guard against a ``dt`` given in ms for s).
MAX_SAMPLES = 10_000_000


class Wavelet(NamedTuple):
    """A wavelet: ``time`` (s, regular, with a sample at 0) and ``amplitude`` (peak 1 for a
    Ricker)."""

    time: np.ndarray
    amplitude: np.ndarray


class Synthetic(NamedTuple):
    """A synthetic: the ``twt`` grid (s), the ``reflectivity`` on it and the ``trace``
    (reflectivity convolved with the wavelet), both ``(..., len(twt))``."""

    twt: np.ndarray
    reflectivity: np.ndarray
    trace: np.ndarray


class AngleGather(NamedTuple):
    """An angle gather: ``twt`` window (s), ``angle`` (degrees), ``gather`` of shape
    ``(..., len(angle), len(twt))`` and ``twt_at`` (s, ``(...)``), the time of the chosen
    depth."""

    twt: np.ndarray
    angle: np.ndarray
    gather: np.ndarray
    twt_at: np.ndarray


def _plain(name, value):
    """``value`` as a float array, refusing pandas and xarray objects by name."""
    if type(value).__module__.partition(".")[0] in ("pandas", "xarray"):
        raise ValueError(f"{name} is a {type(value).__module__.partition('.')[0]} object; give a "
                         "numpy array with depth on its last axis (series.to_numpy(), or "
                         "da.transpose(..., 'depth').values)")
    return as_array(name, value)


def _profile(depth, **arrays):
    """Check a profile: depths (m, >= 0, strictly increasing on the last axis, at least two) and
    positive finite profile arrays of the same last length; returns them broadcast."""
    z = check_range("depth", _plain("depth", depth), 0.0, np.inf, high_open=True)
    if z.ndim == 0 or z.shape[-1] < 2:
        raise ValueError(f"depth must hold at least two samples on its last axis; got shape "
                         f"{z.shape}")
    if np.any(np.diff(z, axis=-1) <= 0.0):
        raise ValueError("depth must increase strictly along its last axis")
    out = {}
    for name, (value, low, high) in arrays.items():
        a = check_range(name, _plain(name, value), low, high, low_open=name != "vs")
        if a.ndim == 0 or a.shape[-1] != z.shape[-1]:
            raise ValueError(f"{name} must have {z.shape[-1]} samples on its last axis (one per "
                             f"depth); got shape {a.shape}")
        out[name] = a
    try:
        shape = np.broadcast_shapes(z.shape, *(a.shape for a in out.values()))
    except ValueError:
        shapes = ", ".join(f"{k} {v.shape}" for k, v in {"depth": z, **out}.items())
        raise ValueError(f"shapes do not broadcast together: {shapes}") from None
    return np.broadcast_to(z, shape), {k: np.broadcast_to(v, shape) for k, v in out.items()}


def _dt(dt):
    d = as_scalar("dt", dt)
    if not 0.0 < d < np.inf:
        raise ValueError(f"dt must be a positive sample interval in s; got {d:g}")
    return d


def _twt(z, vp, datum_velocity):
    if datum_velocity is None:
        vd = vp[..., 0]
    else:
        vd = check_range("datum_velocity", _plain("datum_velocity", datum_velocity), 0.0, 25.0,
                         low_open=True)
    slowness = 2.0 / (1000.0 * vp)                      # two-way s per m
    steps = 0.5 * (slowness[..., 1:] + slowness[..., :-1]) * np.diff(z, axis=-1)
    try:
        t = np.empty(np.broadcast_shapes(z.shape, np.shape(vd) + (1,)))
    except ValueError:
        raise ValueError(f"datum_velocity of shape {np.shape(vd)} does not broadcast against "
                         f"the leading axes of the profile, {z.shape[:-1]}") from None
    t[..., 0] = 2.0 * z[..., 0] / (1000.0 * vd)
    t[..., 1:] = t[..., :1] + np.cumsum(steps, axis=-1)
    return t


def depth_to_twt(depth, vp, *, datum_velocity=None):
    """Two-way vertical travel time at each depth of a profile from its own P velocity.

    .. math:: t(z_i) = \\frac{2 z_0}{v_d} + \\sum_{k<i} (z_{k+1} - z_k)
              \\left(\\frac{1}{v_k} + \\frac{1}{v_{k+1}}\\right)

    the time down from the datum (depth 0) to the first sample at ``datum_velocity`` :math:`v_d`,
    then the trapezoid rule on the slowness :math:`1/v_P` between samples (exact where the
    slowness varies linearly between samples, and for a constant velocity: ``2 z / v``).

    Parameters
    ----------
    depth : array_like
        Depths, m, ``>= 0``, strictly increasing along the last axis (at least two).
    vp : array_like
        P velocity at each depth, km/s, ``> 0``, on the same last axis (leading axes broadcast).
    datum_velocity : float or array_like, optional
        Velocity between the datum and the first depth, km/s, in (0, 25] (broadcast against
        the leading axes); default the first sample's ``vp``.

    Returns
    -------
    ndarray
        Two-way time, s, of the broadcast shape of ``depth`` and ``vp``.

    Examples
    --------
    >>> depth_to_twt([0.0, 1000.0, 2000.0], [2.0, 2.0, 2.0])
    array([0., 1., 2.])
    """
    z, a = _profile(depth, vp=(vp, 0.0, 25.0))
    return _twt(z, a["vp"], datum_velocity)


def ricker(frequency, dt, *, length=None) -> Wavelet:
    """Zero-phase Ricker wavelet ([Ricker1953]_), peak amplitude 1 at time 0.

    .. math:: w(t) = (1 - 2\\pi^2 f^2 t^2)\\, e^{-\\pi^2 f^2 t^2}

    Its amplitude spectrum :math:`W(\\nu) = \\frac{2\\nu^2}{\\sqrt\\pi f^3} e^{-\\nu^2/f^2}`
    peaks at :math:`\\nu = f`, the peak frequency.

    Parameters
    ----------
    frequency : float
        Peak frequency :math:`f`, Hz, in (0, 1/(2 dt)] (the Nyquist frequency; the spectrum above
        ``3 f`` holds less than 0.3 % of its peak, so ``f <= 1/(6 dt)`` keeps aliasing below that).
    dt : float
        Sample interval, s, ``> 0``.
    length : float, optional
        Duration, s; the samples are the multiples of ``dt`` within ``±length/2`` (at least three).
        By default ``±6/(pi f)``, where the envelope :math:`e^{-\\pi^2 f^2 t^2}` is ``e**-36``:
        the truncation changes no value by more than 1e-14.

    Returns
    -------
    Wavelet
        ``time`` (s, an odd number of samples, symmetric about 0) and ``amplitude``.

    Examples
    --------
    >>> w = ricker(25.0, 0.004, length=0.024)
    >>> w.time.round(3).tolist(), w.amplitude.round(3).tolist()[3]
    ([-0.012, -0.008, -0.004, 0.0, 0.004, 0.008, 0.012], 1.0)
    """
    d = _dt(dt)
    f = as_scalar("frequency", frequency)
    if not 0.0 < f <= 0.5 / d:
        raise ValueError(f"frequency must lie in (0, {0.5 / d:g}] Hz (the Nyquist frequency of "
                         f"dt = {d:g} s); got {f:g}")
    if length is None:
        half = 6.0 / (np.pi * f)
    else:
        half = 0.5 * as_scalar("length", length)
        if not 2.0 * d <= 2.0 * half < np.inf:
            raise ValueError(f"length must be at least 2 dt = {2 * d:g} s; got {2 * half:g}")
    n = int(np.floor(half / d * (1.0 + 1e-12)))
    if 2 * n + 1 > MAX_SAMPLES:
        raise ValueError(f"the wavelet would have {2 * n + 1} samples (more than "
                         f"{MAX_SAMPLES}); is dt = {d:g} s in seconds?")
    t = np.arange(-n, n + 1) * d
    x = (np.pi * f * t) ** 2
    return Wavelet(t, (1.0 - 2.0 * x) * np.exp(-x))


def _wavelet(wavelet, dt) -> Wavelet:
    """A number (a Ricker's peak frequency), a (time, amplitude) pair or an odd-length array
    centred on its middle sample."""
    if isinstance(wavelet, (int, float, np.integer, np.floating)) and \
            not isinstance(wavelet, bool):
        return ricker(wavelet, dt)
    if isinstance(wavelet, tuple) and len(wavelet) == 2:
        t = _plain("wavelet time", wavelet[0])
        a = _plain("wavelet amplitude", wavelet[1])
        if t.ndim != 1 or a.shape != t.shape or t.size < 1:
            raise ValueError("wavelet must be (time, amplitude), two 1-D arrays of one length")
        if t.size > 1 and not np.allclose(np.diff(t), dt, rtol=1e-6, atol=0.0):
            raise ValueError(f"wavelet time must be sampled at dt = {dt:g} s")
        i0 = np.flatnonzero(np.abs(t) <= 1e-6 * dt)
        if i0.size != 1:
            raise ValueError("wavelet time must have one sample at time 0")
        return Wavelet(t - t[i0[0]], a)
    a = _plain("wavelet", wavelet)
    if a.ndim != 1 or a.size % 2 == 0:
        raise ValueError("wavelet must be a peak frequency (Hz), a (time, amplitude) pair, or a "
                         "1-D array of an odd number of samples centred on time 0; got shape "
                         f"{a.shape}")
    n = a.size // 2
    return Wavelet(np.arange(-n, n + 1) * dt, a)


def _series(z, vp, vs, rho, dt, angle, datum_velocity, placement):
    """Interface times and coefficients, and the reflectivity on the common time grid."""
    if placement not in ("linear", "nearest"):
        raise ValueError(f"placement must be 'linear' or 'nearest'; got {placement!r}")
    t = _twt(z, vp, datum_velocity)
    tau = 0.5 * (t[..., 1:] + t[..., :-1])           # the interface between samples k and k+1
    ang = check_range("angle", as_array("angle", angle), 0.0, 90.0, high_open=True)
    if ang.ndim > 1:
        raise ValueError(f"angle must be one angle or a 1-D array of angles; got shape "
                         f"{ang.shape}")
    if ang.ndim == 0 and ang == 0.0:
        imp = rho * vp
        r = (imp[..., 1:] - imp[..., :-1]) / (imp[..., 1:] + imp[..., :-1])
    else:
        if vs is None:
            raise ValueError("vs is needed for an angle of incidence above 0")
        sl = (Ellipsis, None, slice(None)) if ang.ndim else (Ellipsis,)
        a_ = ang[:, None] if ang.ndim else ang
        r = zoeppritz_pp(vp[sl][..., :-1], vs[sl][..., :-1], rho[sl][..., :-1],
                         vp[sl][..., 1:], vs[sl][..., 1:], rho[sl][..., 1:], a_).real
        tau = np.broadcast_to(tau[sl], r.shape)
    i_lo = int(np.floor(t[..., 0].min() / dt * (1.0 + 1e-12)))
    i_hi = max(int(np.ceil(t[..., -1].max() / dt * (1.0 - 1e-12))), i_lo + 1)
    n_t = i_hi - i_lo + 1
    if n_t > MAX_SAMPLES:
        raise ValueError(f"the time grid would have {n_t} samples (more than {MAX_SAMPLES}); "
                         f"is dt = {dt:g} s in seconds?")
    grid = np.arange(i_lo, i_hi + 1) * dt
    x = tau / dt - i_lo                               # position on the grid, in samples
    rows = int(np.prod(r.shape[:-1]))
    offset = (np.arange(rows) * n_t).reshape(r.shape[:-1] + (1,))
    if placement == "nearest":
        j = np.clip(np.rint(x).astype(np.int64), 0, n_t - 1)
        series = np.bincount((offset + j).ravel(), r.ravel(), rows * n_t)
    else:
        j = np.clip(np.floor(x).astype(np.int64), 0, n_t - 2)
        w = x - j
        series = (np.bincount((offset + j).ravel(), (r * (1.0 - w)).ravel(), rows * n_t)
                  + np.bincount((offset + j + 1).ravel(), (r * w).ravel(), rows * n_t))
    return t, grid, series.reshape(r.shape[:-1] + (n_t,))


def reflectivity_series(vp, rho, depth, *, dt, vs=None, angle=0.0, datum_velocity=None,
                        placement="linear"):
    """Reflection coefficients of a sampled profile on a regular two-way-time grid.

    Each pair of adjacent samples ``k, k+1`` is an interface, at the mean of their two-way
    times (:func:`depth_to_twt`). Its coefficient is :math:`(Z_{k+1} - Z_k)/(Z_{k+1} + Z_k)`,
    :math:`Z = \\rho V_P`, at normal incidence, else the real part of the exact
    :func:`rockcem.reflectivity.zoeppritz_pp` at ``angle`` (the same angle of incidence at every
    interface, as in a plane-wave angle gather; beyond a critical angle the imaginary part, a
    phase shift, is left out). With ``placement="linear"`` a coefficient at time
    :math:`\\tau` between grid times :math:`t_j \\le \\tau < t_{j+1}` is split between the two
    samples in the proportions :math:`1 - w` and :math:`w`, :math:`w = (\\tau - t_j)/dt`, which
    keeps its sum and its centre of mass in time; ``"nearest"`` puts it whole on the nearest
    sample (up to ``dt/2`` off).

    Parameters
    ----------
    vp, rho : array_like
        P velocity (km/s) and density (g/cm³) at each depth, on the last axis.
    depth : array_like
        Depths, m, as :func:`depth_to_twt`.
    dt : float, keyword-only
        Sample interval of the grid, s. The grid is the multiples of ``dt`` from the first
        sample's time to the last one's (over all leading axes).
    vs : array_like, optional
        S velocity, km/s, in [0, 25]; needed when ``angle > 0`` (then ``> 0``: solids only, as
        :func:`rockcem.reflectivity.zoeppritz_pp`).
    angle : float or 1-D array_like
        Angle(s) of incidence, degrees, in [0, 90); several angles add an axis before time.
    datum_velocity : float or array_like, optional
        As :func:`depth_to_twt`.
    placement : {"linear", "nearest"}
        How a coefficient is put on the grid.

    Returns
    -------
    twt : ndarray
        The grid, s.
    reflectivity : ndarray
        ``(..., [angle,] len(twt))``.
    """
    z, a = _profile(depth, vp=(vp, 0.0, 25.0), rho=(rho, 0.0, 25.0),
                    **({} if vs is None else {"vs": (vs, 0.0, 25.0)}))
    _, grid, series = _series(z, a["vp"], a.get("vs"), a["rho"], _dt(dt), angle,
                              datum_velocity, placement)
    return grid, series


def _convolve(series, wav, n_t):
    i0 = int(np.flatnonzero(wav.time == 0.0)[0])
    kernel = wav.amplitude.reshape((1,) * (series.ndim - 1) + (-1,))
    full = oaconvolve(series, kernel, mode="full", axes=-1)
    return full[..., i0:i0 + n_t]


def synthetic_trace(depth, vp, vs, rho, *, dt, wavelet, angle=0.0, datum_velocity=None,
                    placement="linear") -> Synthetic:
    """Convolutional synthetic of a sampled profile: the reflectivity series
    (:func:`reflectivity_series`) convolved with a wavelet.

    .. math:: s(t_j) = \\sum_k r(t_k)\\, w(t_j - t_k)

    (the convolutional model of a layered earth, primaries only, no transmission losses or
    multiples; [Yilmaz2001]_, chapter 2), the wavelet's time 0 aligned with each reflection.

    Parameters
    ----------
    depth, vp, vs, rho : array_like
        The profile, as :func:`reflectivity_series` (``vs`` may be None at normal incidence).
    dt : float, keyword-only
        Sample interval, s.
    wavelet : float, (time, amplitude) or 1-D array, keyword-only
        A number is the peak frequency (Hz) of a :func:`ricker` wavelet; a pair as ``ricker``
        returns is a wavelet sampled at ``dt`` with a sample at time 0; a 1-D array of an odd
        number of samples at ``dt`` is centred on its middle sample.
    angle, datum_velocity, placement
        As :func:`reflectivity_series`.

    Returns
    -------
    Synthetic
        ``twt`` (s), ``reflectivity`` and ``trace`` (``(..., [angle,] len(twt))``).

    Examples
    --------
    Two samples, 1000 m apart: the interface lies at the mean of their times, (0 + 0.9)/2 s,
    and the trace peaks there at R = (5 - 4)/(5 + 4).

    >>> s = synthetic_trace([0.0, 1000.0], [2.0, 2.5], None, [2.0, 2.0], dt=0.002, wavelet=25.0)
    >>> round(float(s.twt[np.argmax(s.trace)]), 6), round(float(s.trace.max()), 6)
    (0.45, 0.111111)
    """
    d = _dt(dt)
    wav = _wavelet(wavelet, d)
    z, a = _profile(depth, vp=(vp, 0.0, 25.0), rho=(rho, 0.0, 25.0),
                    **({} if vs is None else {"vs": (vs, 0.0, 25.0)}))
    _, grid, series = _series(z, a["vp"], a.get("vs"), a["rho"], d, angle, datum_velocity,
                              placement)
    return Synthetic(grid, series, _convolve(series, wav, grid.size))


def angle_gather(depth, vp, vs, rho, *, at, angles, dt, wavelet, window=None,
                 datum_velocity=None, placement="linear") -> AngleGather:
    """Synthetic angle gather of a profile around a chosen depth.

    One :func:`synthetic_trace` per angle of incidence (the exact PP coefficient at that angle
    for every interface, the vertical two-way time: a plane-wave gather, no moveout), cut to the
    times within ``window`` of the time of depth ``at``.

    Parameters
    ----------
    depth, vp, vs, rho : array_like
        The profile, as :func:`synthetic_trace` (``vs`` required).
    at : float, keyword-only
        The depth of interest, m, within the profile's depths.
    angles : array_like, keyword-only
        Angles of incidence, degrees, in [0, 90), 1-D.
    dt, wavelet : keyword-only
        As :func:`synthetic_trace`.
    window : float, optional
        Half-width of the time window, s, ``> 0``; default the wavelet's duration.
    datum_velocity, placement
        As :func:`reflectivity_series`.

    Returns
    -------
    AngleGather
        ``twt`` (the grid times within the window of any leading index), ``angle``, ``gather``
        ``(..., len(angle), len(twt))`` and ``twt_at`` (``(...)``, s).
    """
    d = _dt(dt)
    wav = _wavelet(wavelet, d)
    ang = check_range("angles", as_array("angles", angles), 0.0, 90.0, high_open=True)
    if ang.ndim != 1 or ang.size == 0:
        raise ValueError(f"angles must be a 1-D array of angles; got shape {ang.shape}")
    if vs is None:
        raise ValueError("vs is needed for an angle gather")
    z, a = _profile(depth, vp=(vp, 0.0, 25.0), vs=(vs, 0.0, 25.0), rho=(rho, 0.0, 25.0))
    at_ = as_scalar("at", at)
    if not z[..., 0].max() <= at_ <= z[..., -1].min():
        raise ValueError(f"at must lie within the profile's depths [{z[..., 0].max():g}, "
                         f"{z[..., -1].min():g}] m; got {at_:g}")
    half = wav.time[-1] - wav.time[0] if window is None else as_scalar("window", window)
    if not 0.0 < half < np.inf:
        raise ValueError(f"window must be a positive half-width in s; got {half:g}")
    t, grid, series = _series(z, a["vp"], a["vs"], a["rho"], d, ang, datum_velocity, placement)
    flat_z = z.reshape(-1, z.shape[-1])
    flat_t = t.reshape(-1, t.shape[-1])
    t_at = np.array([np.interp(at_, zz, tt) for zz, tt in zip(flat_z, flat_t)]).reshape(
        t.shape[:-1])
    keep = (grid >= t_at.min() - half) & (grid <= t_at.max() + half)
    trace = _convolve(series, wav, grid.size)
    return AngleGather(grid[keep], ang, trace[..., keep], t_at)
