"""Sweeps of a pillar sensor in time, over frequency, mean stress and amplitude (issue 31,
theory.md §14), as xarray datasets, eager or chunked with dask.

- :func:`response_sweep`: the linear frequency response H(f) [m/Pa] over a grid of
  (mean stress, frequency): one linearisation per mean stress
  (:func:`hairbed.sensor_dynamics.frequency_response`'s model), its transfer function at the
  block's frequencies.
- :func:`amplitude_sweep`: the nonlinear pillar's periodic response to tau_w(t) = tau_mean +
  a sin(2 pi f t) over a grid of (amplitude, frequency), by :func:`hairbed.sensor_dynamics.
  simulate` (the quasi-steady drag with added mass): its first harmonic per stress amplitude
  (-> the linear H as a -> 0, the difference O(a^2)), the shift of its mean and its
  harmonic distortion, with the linear response beside it.

With ``chunks=`` the dataset is dask-backed and lazy; each block is computed when the
dataset is (the threaded scheduler by default, a ``dask.distributed`` cluster when a
``Client`` exists). Chunks along the mean stress or the amplitude are bitwise the eager
sweep; a chunk of frequencies of :func:`response_sweep` is solved as its own band (one LU a
frequency or the Schur form, theory.md §14), the same to rounding (2e-16 measured).

Measured (tests/test_sweeps_response.py): a glycerol pillar at 1 Pa (x1 = 0.056 L), a =
0.05 and 0.1 Pa at 0.5 and 2 Hz: the first harmonic per amplitude within 7.3e-6 and 2.9e-5
of the linear H (ratio 4.00 and 3.99: O(a^2)), the mean shift's ratio 4.0 and the
distortion's 2.0.
"""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .. import sensor_dynamics as sd
from .._core.validation import as_float_array, check_int, check_number, show
from .._optional import optional_import
from .._version import __version__
from ._blocks import stacked

__all__ = [
    "AMPLITUDE_STATUS",
    "AMPLITUDE_VARIABLES",
    "RESPONSE_VARIABLES",
    "amplitude_sweep",
    "response_sweep",
]

FloatArray = NDArray[np.float64]

#: The variables of :func:`response_sweep`: name -> (units, long_name).
RESPONSE_VARIABLES: dict[str, tuple[str, str]] = {
    "response_real": ("m/Pa", "Re H, tip deflection per wall shear stress (exp(i 2 pi f t))"),
    "response_imag": ("m/Pa", "Im H, tip deflection per wall shear stress (exp(i 2 pi f t))"),
    "magnitude": ("m/Pa", "|H|, tip deflection per wall shear stress"),
    "phase": ("rad", "arg H (a lag is negative)"),
    "status": ("1", "status of the linear response (0 ok, 3 beyond the resolution)"),
}
#: The variables of :func:`amplitude_sweep`: name -> (units, long_name).
AMPLITUDE_VARIABLES: dict[str, tuple[str, str]] = {
    "harmonic_gain": ("m/Pa", "|X1|/a: first harmonic of the tip deflection per stress amplitude"),
    "harmonic_phase": ("rad", "arg(X1) - arg(a): its phase against the drive's"),
    "linear_gain": ("m/Pa", "|H|: the linear response at the mean stress (quasi-steady drag)"),
    "linear_phase": ("rad", "arg H: the linear response's phase"),
    "mean_shift": ("m", "mean tip deflection over the periods less the static one at the mean"),
    "distortion": ("1", "rms of the harmonics 2 to 8 over the first, of the tip deflection"),
    "periodicity": ("m", "largest change of the tip deflection over the last period"),
    "status": ("1", "0 periodic; 1 not periodic to periodic_tol; negative: the run's status"),
}
#: Status codes of an amplitude sweep's cell (the run's own negative codes are kept).
AMPLITUDE_STATUS = {
    0: "ok: periodic to periodic_tol",
    1: "not periodic to periodic_tol over the last period: give a longer settle time",
}
#: Samples per period of the amplitude sweep's runs (harmonics up to 8 resolved exactly by
#: the discrete Fourier sum over whole periods).
_SAMPLES = 64
_HARMONICS = 8
_COORDS = {
    "frequency": ("Hz", "frequency"),
    "wall_shear_stress": ("Pa", "mean wall shear stress"),
    "amplitude": ("Pa", "amplitude of the wall shear stress, tau_mean + a sin(2 pi f t)"),
}


#: The frequencies [Hz] an amplitude sweep takes (the run's times and rates stay finite).
_MIN_FREQUENCY, _MAX_FREQUENCY = 1e-100, 1e100


def _axis(value: Any, name: str, unit: str, low: float | None = None) -> FloatArray:
    """A scalar or 1-D axis [unit], finite (and >= low), not empty."""
    arr = as_float_array(value, name, unit=unit)
    if arr.ndim > 1 or arr.size == 0:
        raise ValueError(f"{name} must be a number or a non-empty 1-D array [{unit}]")
    if low is not None:
        bad = np.flatnonzero(arr.reshape(-1) < low)
        if bad.size:
            i = int(bad[0])
            raise ValueError(
                f"{name} must be >= {low:g} {unit}, got {show(float(arr.reshape(-1)[i]))}"
                + (f" (first at index {i})" if arr.ndim else "")
            )
    return arr


def _grid_dataset(
    xr: Any,
    data: Any,
    table: dict[str, tuple[str, str]],
    dims: tuple[str, ...],
    values: dict[str, FloatArray],
    attrs: dict[str, Any],
) -> Any:
    data_vars = {}
    for k, (name, (units, long_name)) in enumerate(table.items()):
        v = data[k]
        if name == "status":
            v = v.astype(np.int64)
        data_vars[name] = (dims, v, {"units": units, "long_name": long_name})
    coords = {
        d: ((d,) if d in dims else (), values[d], {"units": u, "long_name": ln})
        for d, (u, ln) in _COORDS.items()
        if d in values
    }
    return xr.Dataset(data_vars, coords=coords, attrs=attrs)


def _base_attrs(title: str, pillar: Any, rho_s: float, drag: str) -> dict[str, Any]:
    return {
        "title": title,
        "Conventions": "CF-1.8",
        "source": f"hairbed {__version__}",
        "hairbed_version": __version__,
        "pillar": repr(pillar),
        "pillar_density_kg_m3": rho_s,
        "drag": drag,
        "time_convention": "exp(i 2 pi f t)",
    }


def _response_block(
    *axes: FloatArray,
    dims: tuple[str, ...],
    pillar: Any,
    tau: float,
    rho_s: float,
    drag: str,
    progress: Any,
) -> FloatArray:
    """One block of :func:`response_sweep`: (5, *block shape)."""
    if progress is not None:
        progress.start()
    if "wall_shear_stress" in dims:
        stresses = axes[0]
        freq = axes[1] if len(axes) > 1 else np.zeros(1)
    else:
        stresses = np.array([tau])
        freq = axes[0] if axes else np.zeros(1)
    out = np.empty((5, stresses.size, freq.size))
    for i, t in enumerate(stresses):
        model = sd._model(pillar, float(t), rho_s, drag)
        h, status = model.response(np.asarray(freq, dtype=np.float64))
        out[:, i] = (h.real, h.imag, np.abs(h), np.angle(h), status)
    shape = tuple(a.size for a in axes)
    if progress is not None:
        progress.update(int(np.prod(shape, dtype=np.int64)))
    return out.reshape((5, *shape))


def response_sweep(
    pillar: Any,
    frequency: Any,
    wall_shear_stress: Any = 0.0,
    *,
    pillar_density: float | None = None,
    drag: str = "sader",
    chunks: Any = None,
) -> Any:
    """A pillar sensor's linear frequency response over (mean stress, frequency).

    At each mean stress tau_mean the pillar is linearised about its static state
    (:func:`hairbed.sensor_dynamics.frequency_response`, theory.md §14; the 'wall-law'
    profile's change of shape included exactly) and its transfer function

        H(f) = L (Lambda/tau_w) H_V(2 pi f T)   [m/Pa]

    evaluated at the frequencies f [Hz]. Every 1-D input is a dimension, in the order
    (wall_shear_stress, frequency); a scalar is a scalar coordinate.

    Parameters
    ----------
    pillar : hairbed.Pillar
        The sensor, with its fluid's density.
    frequency : float or 1-D array
        f >= 0 [Hz].
    wall_shear_stress : float or 1-D array, optional
        The mean stress tau_mean [Pa] of each linearisation (default 0).
    pillar_density : float
        The pillar's density [kg/m^3] (its inertia).
    drag : {"sader", "quasi-steady"}
        The drag model (``sensor_dynamics.DRAG_MODELS``).
    chunks : int or dict, optional
        Chunk lengths per dimension (an int for all): a dask-backed, lazy dataset.

    Returns
    -------
    xarray.Dataset
        ``RESPONSE_VARIABLES`` (units and long_name on each), coordinates ``frequency``
        [Hz] and ``wall_shear_stress`` [Pa]; a ModelValidityWarning for frequencies above
        the model's range (once, at the first mean stress). Needs the ``sweep`` extra.
    """
    xr = optional_import("xarray", "response_sweep", "sweep")
    p = sd._as_pillar(pillar)
    values = {
        "wall_shear_stress": _axis(wall_shear_stress, "wall_shear_stress", "Pa"),
        "frequency": _axis(frequency, "frequency", "Hz", low=0.0),
    }
    dims = tuple(d for d in values if values[d].ndim == 1)
    first = float(values["wall_shear_stress"].reshape(-1)[0])
    model = sd._model(p, first, pillar_density, drag)  # checks density and drag up front
    sd._warn_validity(model, values["frequency"].reshape(-1), stacklevel=3)
    axes = [values[d] for d in dims]
    data = stacked(
        _response_block,
        axes,
        dims,
        5,
        chunks,
        None,
        dims=dims,
        pillar=p,
        tau=first,
        rho_s=model.pillar_density,
        drag=model.drag,
    )
    attrs = _base_attrs(
        "hairbed pillar sensor frequency response over mean stress and frequency",
        p,
        model.pillar_density,
        model.drag,
    )
    return _grid_dataset(xr, data, RESPONSE_VARIABLES, dims, values, attrs)


def _harmonics(
    pillar: Any,
    amp: float,
    freq: float,
    tau: float,
    rho_s: float,
    settle: float,
    periods: int,
    num: int,
    rtol: float,
    max_steps: int,
    periodic_tol: float,
    static: float,
    gain: float,
) -> tuple[float, ...]:
    """One cell: (|X1|/a, arg, mean shift, distortion, periodicity, status); ``gain`` the
    linear |H| [m/Pa] (the motion's scale, for the integrator's absolute tolerance)."""
    from ..dynamics import sine

    omega = 2.0 * math.pi * freq
    period = 1.0 / freq
    t0 = math.ceil(settle / period) * period  # whole periods before the analysis
    n = _SAMPLES * periods
    t = t0 + period * np.arange(n + 1) / _SAMPLES
    run = sd.simulate(
        pillar,
        sine(tau, amp, omega),
        np.concatenate([[0.0], t]),  # from the static state at tau_mean at t = 0
        pillar_density=rho_s,
        num=num,
        rtol=rtol,
        # the angles' absolute tolerance at the motion's own scale (|H| a/L rad)
        atol=max(rtol * gain * amp / pillar.length, 1e-300),
        max_steps=max_steps,
    )
    if run.status < 0:
        return (math.nan,) * 5 + (float(run.status),)
    x = np.asarray(run.tip_deflection[1:], dtype=np.float64)
    last = x[n - _SAMPLES : n + 1]
    before = x[n - 2 * _SAMPLES : n - _SAMPLES + 1] if periods >= 2 else last
    change = float(np.max(np.abs(last - before)))
    spec = np.fft.rfft(x[:n]) * (2.0 / n)  # whole periods: harmonic k at bin k periods
    harm = spec[periods * np.arange(1, _HARMONICS + 1)]
    # t_j = t0 + j/(64 f), t0 whole periods: (2/n) sum x_j e^{-i w t_j} is x1 of
    # X1 = Re(x1 e^{i w t}); the drive a sin(w t) = Re(-i a e^{i w t})
    x1 = harm[0]
    h1 = x1 / (-1j * amp)
    dist = float(np.sqrt(np.sum(np.abs(harm[1:]) ** 2)) / abs(harm[0]))
    mean = float(np.mean(x[:n])) - static
    scale = max(abs(x1), 1e-300)
    status = 0 if change <= periodic_tol * scale else 1
    return (abs(h1), float(np.angle(h1)), mean, dist, change, float(status))


def _amplitude_block(
    *axes: FloatArray,
    dims: tuple[str, ...],
    values: dict[str, FloatArray],
    pillar: Any,
    tau: float,
    rho_s: float,
    settle: float,
    periods: int,
    num: int,
    rtol: float,
    max_steps: int,
    periodic_tol: float,
    static: float,
    linear: tuple[FloatArray, FloatArray],
    progress: Any,
) -> FloatArray:
    """One block of :func:`amplitude_sweep`: (8, *block shape)."""
    if progress is not None:
        progress.start()
    got = dict(zip(dims, axes))
    amps = got.get("amplitude", values["amplitude"].reshape(-1))
    freqs = got.get("frequency", values["frequency"].reshape(-1))
    out = np.empty((8, amps.size, freqs.size))
    all_f = values["frequency"].reshape(-1)
    for j, f in enumerate(freqs):
        k = int(np.flatnonzero(all_f == f)[0])
        for i, a in enumerate(amps):
            cell = _harmonics(
                pillar,
                float(a),
                float(f),
                tau,
                rho_s,
                settle,
                periods,
                num,
                rtol,
                max_steps,
                periodic_tol,
                static,
                float(linear[0][k]),
            )
            out[:, i, j] = (
                cell[0],
                cell[1],
                linear[0][k],
                linear[1][k],
                cell[2],
                cell[3],
                cell[4],
                cell[5],
            )
    shape = tuple(a.size for a in axes)
    if progress is not None:
        progress.update(int(np.prod(shape, dtype=np.int64)))
    return out.reshape((8, *shape))


def amplitude_sweep(
    pillar: Any,
    amplitude: Any,
    frequency: Any,
    *,
    wall_shear_stress: float = 0.0,
    pillar_density: float | None = None,
    periods: int = 4,
    settle_tol: float = 1e-6,
    periodic_tol: float = 1e-4,
    num: int = 12,
    rtol: float = 1e-8,
    max_steps: int = 200_000,
    chunks: Any = None,
) -> Any:
    """The nonlinear pillar's periodic response over (amplitude, frequency).

    Each cell integrates the pillar in time (:func:`hairbed.sensor_dynamics.simulate`, the
    quasi-steady drag with the fluid's added mass, theory.md §14) under

        tau_w(t) = tau_mean + a sin(2 pi f t)   [Pa]

    from the static state at tau_mean, for a settling time t_s = ln(1/settle_tol)/delta
    (delta the slowest decay rate of the linear modes at tau_mean [1/s]) rounded up to whole
    periods, then ``periods`` periods sampled 64 times each. Over those, the tip deflection's
    Fourier coefficients x_k at k f give the first harmonic per stress amplitude,
    H_1 = x_1/(-i a) [m/Pa] (-> the linear H(f) as a -> 0, their difference O(a^2)), the
    harmonic distortion sqrt(sum_{k=2}^{8} abs(x_k)^2)/abs(x_1) and the mean's shift from the
    static deflection at tau_mean [m] (O(a^2), the static curve's curvature and the
    dynamics'). The last period is compared with the one before: a change above
    ``periodic_tol`` abs(x_1) is status 1 (not yet periodic).

    Parameters
    ----------
    pillar : hairbed.Pillar
        The sensor ('sublayer', 'couette', 'poiseuille' or a callable profile: the
        'wall-law' pillar cannot be integrated in time), with its fluid's density.
    amplitude : float or 1-D array
        a > 0 [Pa].
    frequency : float or 1-D array
        f [Hz] in [1e-100, 1e100].
    wall_shear_stress : float
        tau_mean [Pa].
    pillar_density : float
        The pillar's density [kg/m^3].
    periods : int
        Whole periods analysed (>= 2; default 4).
    settle_tol : float
        The transient's decay before the analysis, in (0, 1) (default 1e-6).
    periodic_tol : float
        The periodicity a cell must reach (relative to abs(x_1); default 1e-4).
    num, rtol, max_steps :
        The integrator's Chebyshev degree, relative tolerance and step bound per cell.
    chunks : int or dict, optional
        Chunk lengths per dimension: a dask-backed, lazy dataset.

    Returns
    -------
    xarray.Dataset
        ``AMPLITUDE_VARIABLES`` over the dimensions (amplitude, frequency) that are 1-D;
        ``AMPLITUDE_STATUS`` in ``status`` (negative: the run's own code). Needs the
        ``sweep`` extra.
    """
    xr = optional_import("xarray", "amplitude_sweep", "sweep")
    p = sd._as_pillar(pillar)
    if p.profile == "wall-law":
        raise ValueError(
            "amplitude_sweep() integrates in time, which a 'wall-law' pillar cannot (its "
            "profile changes shape with tau_w(t)): use response_sweep for its linear response"
        )
    values = {
        "amplitude": _axis(amplitude, "amplitude", "Pa", low=0.0),
        "frequency": _axis(frequency, "frequency", "Hz", low=0.0),
    }
    for name in values:
        zero = np.flatnonzero(values[name].reshape(-1) == 0.0)
        if zero.size:
            raise ValueError(f"{name} must be > 0, got 0 (first at index {int(zero[0])})")
    # the run spans periods/f [s] and drives at 2 pi f [rad/s]: both finite in the units of
    # the dynamics (as the stress series' sample rate, sensor_dynamics)
    f_all = values["frequency"].reshape(-1)
    off = np.flatnonzero(~((f_all >= _MIN_FREQUENCY) & (f_all <= _MAX_FREQUENCY)))
    if off.size:
        i = int(off[0])
        raise ValueError(
            f"frequency must lie in [{_MIN_FREQUENCY:g}, {_MAX_FREQUENCY:g}] Hz, got "
            f"{show(float(f_all[i]))} (first at index {i})"
        )
    tau = check_number(wall_shear_stress, "wall_shear_stress", unit="Pa")
    values["wall_shear_stress"] = np.asarray(tau)
    # the run's drive tau + a sin(...) within the dynamics' bound on the forcing [Pa]
    top = sd.MAX_DRIVE / p.forcing_per_stress - abs(tau)
    over = np.flatnonzero(~(values["amplitude"].reshape(-1) <= top))
    if over.size:
        i = int(over[0])
        raise ValueError(
            f"amplitude must be at most {top:.4g} Pa for this pillar about wall_shear_stress = "
            f"{show(tau)} Pa (the drive's magnitude within {sd.MAX_DRIVE:g}/(Lambda/tau_w)), "
            f"got {show(float(values['amplitude'].reshape(-1)[i]))} Pa (first at index {i})"
        )
    per = check_int(periods, "periods", 2, 10_000)
    stol = check_number(settle_tol, "settle_tol", low=0.0, high=1.0, low_open=True, high_open=True)
    ptol = check_number(periodic_tol, "periodic_tol", low=0.0, low_open=True)
    num = check_int(num, "num", 4, 128)
    rt = check_number(rtol, "rtol", low=1e-13, high=1e-2)
    steps = check_int(max_steps, "max_steps", 1, 10**9)
    model = sd._model(p, tau, pillar_density, "quasi-steady")
    rate = -float(np.max(model.lin.modes(4).eigenvalues.real))  # [1/T]
    if not rate > 0.0:
        raise ValueError(
            f"the static state at wall_shear_stress = {show(tau)} Pa is not stable (its "
            "slowest mode does not decay): no periodic response about it"
        )
    settle = math.log(1.0 / stol) / rate * model.time_scale  # [s]
    freqs = values["frequency"].reshape(-1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the validity warning once, below
        h, _ = model.response(freqs)
    sd._warn_validity(model, freqs, stacklevel=3)
    static = float(p.deform(tau).tip_deflection)
    dims = tuple(d for d in ("amplitude", "frequency") if values[d].ndim == 1)
    data = stacked(
        _amplitude_block,
        [values[d] for d in dims],
        dims,
        8,
        chunks,
        None,
        dims=dims,
        values=values,
        pillar=p,
        tau=tau,
        rho_s=model.pillar_density,
        settle=settle,
        periods=per,
        num=num,
        rtol=rt,
        max_steps=steps,
        periodic_tol=ptol,
        static=static,
        linear=(np.abs(h), np.angle(h)),
    )
    attrs = _base_attrs(
        "hairbed pillar sensor: nonlinear periodic response over amplitude and frequency",
        p,
        model.pillar_density,
        "quasi-steady",
    )
    attrs.update(
        settle_time_s=settle,
        periods=np.int64(per),
        settle_tol=stol,
        periodic_tol=ptol,
        static_tip_deflection_m=static,
    )
    return _grid_dataset(xr, data, AMPLITUDE_VARIABLES, dims, values, attrs)
