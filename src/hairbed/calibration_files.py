"""Calibration files: a :class:`~hairbed.calibration.CalibrationFit` written whole and read back.

A calibration is only meaningful with the bed it was fitted on, so the file holds the whole
bed (every parameter, fitted or fixed), the fitted parameters with their standard errors,
covariance and starting values, the fit's chi2 and status, the SHA-256 of the calibration
points (:func:`hairbed.calibration.points_fingerprint`: which data it came from) and the
version of hairbed that wrote it. ``hairbed calibrate --json`` prints this document and
``hairbed measure --calibration`` reads it.

The format is JSON (strict: non-finite numbers are the strings "inf", "-inf", "nan")::

    {"format": "hairbed calibration", "format_version": 1, "hairbed_version": "...",
     "bed": {"length": ..., ..., "density": null, "model": "dense", "drag": "crossover"},
     "geometry": "spacing",
     "kind": "velocity", "points": 10,
     "data": {"kind": "velocity", "points": 10, "weighted": true, "sha256": "..."},
     "parameters": {"youngs_modulus": {"value": ..., "stderr": ..., "start": ...,
                                       "unit": "Pa"}},
     "covariance": [[...]], "chi2": ..., "chi2_unit": "1", "dof": 8, "residuals": [...],
     "success": true, "status": 0, "message": "...", "nfev": 7, "nit": 6,
     "solver_status": 1}

A calibration of an isolated pillar (:class:`hairbed.Pillar`) has ``"sensor": "pillar"`` and
its "bed" holds the Pillar's fields (length, radius, youngs_modulus, viscosity, base_angle,
profile, channel_height, density, drag_scale; a callable profile is not data and is refused)
and no "geometry" (a bed's choice of spacing or packing fraction); without "sensor" the file
is a bed's. A variance (the covariance's diagonal) or standard error below 0 is refused; a
parameter a failed fit did not determine (status -4) has the value "nan".
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Mapping
from types import MappingProxyType
from typing import Any

import numpy as np

from ._variables import BED, names
from ._version import __version__
from .calibration import FREE_PARAMETERS, PILLAR_FREE_PARAMETERS, CalibrationFit
from .pillars import Pillar
from .safe_files import write_text
from .units import HairBed

__all__ = [
    "FORMAT",
    "FORMAT_VERSION",
    "calibration_from_dict",
    "calibration_to_dict",
    "read_calibration",
    "write_calibration",
]

#: The ``format`` entry of a calibration file.
FORMAT = "hairbed calibration"
#: The version of the file layout this module writes (and the newest it reads).
FORMAT_VERSION = 1
#: The bed's parameters, as the file's "bed" holds them (HairBed's dataclass fields), its
#: model and drag law included (a file without them is a dense bed's, the default).
_BED_FIELDS = names(BED, "bed") + names(BED, "bed_model")
#: The pillar's parameters, as the file's "bed" of a pillar holds them (Pillar's fields).
_PILLAR_FIELDS = (
    "length",
    "radius",
    "youngs_modulus",
    "viscosity",
    "base_angle",
    "profile",
    "channel_height",
    "density",
    "drag_scale",
)


def _number(x: float) -> float | str:
    """A float for strict JSON: non-finite values as the strings "inf", "-inf", "nan"."""
    x = float(x)
    return x if math.isfinite(x) else str(x)


def _float(x: Any, where: str) -> float:
    if isinstance(x, bool) or not isinstance(x, int | float | str):
        raise ValueError(f"{where} must be a number, got {x!r}")
    try:
        return float(x)
    except ValueError:
        raise ValueError(f"{where} must be a number, got {x!r}") from None


def _int(x: Any, where: str) -> int:
    """A whole number of a document (a count, a status), or a ValueError naming ``where``."""
    if isinstance(x, bool) or not isinstance(x, int | float) or not float(x).is_integer():
        raise ValueError(f"{where} must be a whole number, got {x!r}")
    return int(x)


def calibration_to_dict(fit: CalibrationFit) -> dict[str, Any]:
    """The calibration file's document of ``fit`` (module docstring), JSON-ready."""
    if not isinstance(fit, CalibrationFit):
        raise TypeError(f"fit must be a hairbed.calibration.CalibrationFit, got {type(fit)}")
    bed = fit.bed
    pillar = isinstance(bed, Pillar)
    if isinstance(bed, Pillar) and callable(bed.profile):
        raise ValueError(
            "a calibration of a pillar with a callable profile cannot be written to a file "
            "(the function is not data): use a built-in profile"
        )
    units = PILLAR_FREE_PARAMETERS if pillar else FREE_PARAMETERS

    def value(k: str) -> Any:
        v = getattr(bed, k)
        return v if v is None or isinstance(v, str) else float(v)

    return {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "hairbed_version": __version__,
        **({"sensor": "pillar"} if pillar else {}),
        "bed": {k: value(k) for k in (_PILLAR_FIELDS if pillar else _BED_FIELDS)},
        # a bed's choice of spacing or packing fraction; a pillar has neither (issue 33)
        **({} if pillar else {"geometry": fit.geometry}),
        "kind": fit.kind,
        "points": int(np.size(fit.residuals)),
        "data": {
            "kind": fit.kind,
            "points": int(np.size(fit.residuals)),
            "weighted": fit.weighted,
            "sha256": fit.fingerprint,
        },
        "parameters": {
            p: {
                "value": _number(fit.values[p]),
                "stderr": _number(fit.stderr[p]),
                "start": _number(fit.start.get(p, math.nan)),
                "unit": units[p],
            }
            for p in fit.parameters
        },
        "covariance": [[_number(c) for c in row] for row in np.asarray(fit.covariance)],
        "chi2": _number(fit.chi2),
        "chi2_unit": fit.chi2_unit,
        "dof": int(fit.dof),
        "residuals": [_number(r) for r in np.asarray(fit.residuals).reshape(-1)],
        "success": bool(fit.success),
        "status": int(fit.status),
        "message": fit.message,
        "nfev": int(fit.nfev),
        "nit": int(fit.nit),
        "solver_status": int(fit.solver_status),
    }


def calibration_from_dict(data: Mapping[str, Any], *, source: str = "data") -> CalibrationFit:
    """The :class:`CalibrationFit` of a calibration file's document (module docstring).

    Parameters
    ----------
    data : Mapping
        The document (the file's JSON object).
    source : str
        What the document is called in error messages (:func:`read_calibration` gives the
        file's path).

    Raises
    ------
    TypeError
        If ``data`` is not a mapping.
    ValueError
        If it is not such a document (message starting with ``source``): an unknown format
        or a newer version, no bed (the output of hairbed before the bed was stored), a bed
        that is not valid, a fitted value the bed does not hold, or a covariance of the wrong
        shape.
    """
    if not isinstance(data, Mapping):
        raise TypeError(
            f"data must be a mapping (a calibration file's JSON object), got {type(data).__name__}"
        )
    if data.get("format") != FORMAT:
        raise ValueError(
            f'{source}: not a hairbed calibration file (no "format": "{FORMAT}"; written '
            "by an older hairbed? re-run 'hairbed calibrate --json')"
        )
    version = data.get("format_version")
    if not isinstance(version, int) or not 1 <= version <= FORMAT_VERSION:
        raise ValueError(
            f"{source}: format_version {version!r} is not one this hairbed reads "
            f"(1 to {FORMAT_VERSION})"
        )
    sensor = data.get("sensor", "bed")
    if sensor not in ("bed", "pillar"):
        raise ValueError(f"{source}: sensor must be 'bed' or 'pillar', got {sensor!r}")
    try:
        bed_fields = dict(data["bed"])
        # a pillar's file has no geometry (those of hairbed before issue 33 said "spacing")
        geometry = str(data.get("geometry", "spacing") if sensor == "pillar" else data["geometry"])
        info = dict(data["data"])
        params = dict(data["parameters"])
        cov = np.array(
            [[_float(c, f"{source}: covariance") for c in row] for row in data["covariance"]],
            dtype=np.float64,
        ).reshape(len(params), len(params))
        residuals = np.array(
            [_float(r, f"{source}: residuals") for r in data["residuals"]], dtype=np.float64
        )
    except (KeyError, TypeError, ValueError) as exc:
        raise ValueError(f"{source}: incomplete calibration file ({exc})") from None
    if geometry not in ("spacing", "packing_fraction"):
        raise ValueError(f"{source}: geometry must be spacing or packing_fraction")
    variance = np.diag(cov)
    negative = variance < 0.0
    if np.any(negative):
        k = int(np.flatnonzero(negative)[0])
        raise ValueError(
            f"{source}: covariance: the variance of {list(params)[k]} is negative "
            f"({float(variance[k])!r}); a variance is >= 0 (or NaN: not determined)"
        )
    fields = _PILLAR_FIELDS if sensor == "pillar" else _BED_FIELDS
    allowed = PILLAR_FREE_PARAMETERS if sensor == "pillar" else FREE_PARAMETERS
    unknown = set(bed_fields) - set(fields)
    if unknown:
        raise ValueError(f"{source}: unknown {sensor} parameter(s) {sorted(unknown)}")
    other = "packing_fraction" if geometry == "spacing" else "spacing"
    kwargs = {k: v for k, v in bed_fields.items() if k != other and v is not None}
    bed: HairBed | Pillar
    try:
        bed = Pillar(**kwargs) if sensor == "pillar" else HairBed(**kwargs)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{source}: the {sensor} is not valid: {exc}") from None
    for p, entry in params.items():
        if p not in allowed:
            raise ValueError(f"{source}: unknown fitted parameter {p!r}")
        value = _float(entry.get("value"), f"{source}: {p} value")
        stderr = _float(entry.get("stderr"), f"{source}: {p} stderr")
        if stderr < 0.0:
            raise ValueError(f"{source}: the {p} stderr {stderr!r} is negative")
        if math.isnan(value):  # not determined by a failed fit (status -4): the bed's start
            continue
        if not math.isclose(value, float(getattr(bed, p)), rel_tol=1e-12):
            raise ValueError(
                f"{source}: the fitted {p} = {value!r} is not the bed's {getattr(bed, p)!r}"
            )
    names_ = tuple(params)
    return CalibrationFit(
        bed=bed,
        parameters=names_,
        values=MappingProxyType(
            {
                p: math.nan
                if math.isnan(_float(params[p].get("value"), p))
                else float(getattr(bed, p))
                for p in names_
            }
        ),
        stderr=MappingProxyType(
            {p: _float(params[p].get("stderr"), f"{source}: {p} stderr") for p in names_}
        ),
        covariance=cov,
        residuals=residuals,
        chi2=_float(data.get("chi2", "nan"), f"{source}: chi2"),
        dof=_int(data.get("dof", len(residuals) - len(names_)), f"{source}: dof"),
        kind=str(info.get("kind", "velocity")),
        success=bool(data.get("success", False)),
        status=_int(data.get("status", 0), f"{source}: status"),
        message=str(data.get("message", "")),
        nfev=_int(data.get("nfev", 0), f"{source}: nfev"),
        nit=_int(data.get("nit", 0), f"{source}: nit"),
        solver_status=_int(data.get("solver_status", 0), f"{source}: solver_status"),
        geometry=geometry,
        weighted=bool(info.get("weighted", True)),
        fingerprint=str(info.get("sha256", "")),
        start=MappingProxyType(
            {p: _float(params[p].get("start", "nan"), f"{source}: {p} start") for p in names_}
        ),
    )


def write_calibration(fit: CalibrationFit, path: str | os.PathLike[str]) -> None:
    """Write ``fit`` to the JSON calibration file ``path``, whole or not at all
    (:mod:`hairbed.safe_files`)."""
    write_text(path, json.dumps(calibration_to_dict(fit), indent=1) + "\n")


def read_calibration(path: str | os.PathLike[str]) -> CalibrationFit:
    """Read a calibration file written by :func:`write_calibration` or ``hairbed calibrate
    --json``.

    Raises
    ------
    OSError
        The file cannot be read.
    ValueError
        It is not a calibration file (:func:`calibration_from_dict`), is JSON but not an
        object (``[1, 2, 3]``, ``42``, ``null``) or is nested too deeply to read; the message
        starts with the path.
    """
    with open(path) as fh:
        text = fh.read()
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise ValueError(f"{path}: not JSON ({exc})") from None
    except RecursionError:  # arrays or objects nested thousands deep
        raise ValueError(f"{path}: not a calibration file (JSON nested too deeply)") from None
    if not isinstance(data, dict):  # [1, 2, 3], 42, null, "text", ...
        names = {list: "array", int: "number", float: "number", str: "string", bool: "boolean"}
        kind = "null" if data is None else names.get(type(data), type(data).__name__)
        raise ValueError(
            f"{path}: not a calibration file (a JSON object with a bed and its parameters), "
            f"got a JSON {kind}"
        )
    return calibration_from_dict(data, source=str(path))
