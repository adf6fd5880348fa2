"""The drag coefficients of a hair in a bed: isolated, in an array, and the crossover.

The porous bed (theory.md §13) needs the normal and tangential drag per unit length and
speed of one hair, zeta_perp and zeta_par; its two numbers follow from them, the permeability
kappa = eta A/(zeta_perp L^2) and the drag ratio gamma = zeta_par/zeta_perp. Each coefficient
is written as a slender-body one, 4 pi eta/Lambda_perp and 2 pi eta/Lambda_par, whose
logarithm Lambda is cut off at a length:

* "sparse": Gray & Hancock (J. Exp. Biol. 32, 802, 1955), cut off at the hair's length:
  Lambda_perp = ln(2L/a) + 1/2, Lambda_par = ln(2L/a) - 1/2;
* "array": the array's own, from the Darcy permeabilities of the hexagonal array (Drummond &
  Tahir, Int. J. Multiphase Flow 10, 515, 1984), zeta = eta A/k: Lambda_perp = 4 pi k_perp/A,
  Lambda_par = 2 pi k_par/A, cut off at the array's screening length (~ the spacing);
* "crossover" (default): the logarithm cut off at the harmonic combination of the two lengths
  measured from the hair's surface, l - a with 1/(l - a) = 1/(l_sparse - a) + 1/(l_array - a),
  l = a e^Lambda: Lambda = ln(1 + 1/(1/(e^Lambda_sparse - 1) + 1/(e^Lambda_array - 1))). It
  is the shorter length's Lambda wherever the two differ much, continuous and smooth in
  between, and positive for any positive pair.
"""

from __future__ import annotations

import math

from ._core.validation import check_choice

__all__ = [
    "DRAG_MODELS",
    "MAX_PACKING_FRACTION",
    "drag_coefficients",
    "drag_logarithm_slopes",
    "parallel_permeability",
]

DRAG_MODELS = ("crossover", "sparse", "array")
#: The array's permeabilities (Drummond & Tahir's fits) hold while the transverse one falls
#: with phi: beyond this the fitted k_perp turns up (and gamma = k_perp/k_par passes 1 at 0.63).
MAX_PACKING_FRACTION = 0.6


def parallel_permeability(radius: float, phi: float) -> float:
    """Darcy permeability k_par [m^2] of a hexagonal array of cylinders for flow along their
    axes (Drummond & Tahir 1984): k_par/a^2 = (-ln phi - 1.498 + 2 phi - phi^2/2 -
    0.0018 phi^6)/(4 phi). Inputs checked by the caller."""
    series = -math.log(phi) - 1.498 + 2.0 * phi - 0.5 * phi**2 - 0.0018 * phi**6
    return radius * (radius * series / (4.0 * phi))


def _cut(sparse: float, array: float) -> float:
    """The crossover's logarithm of two positive logarithms (module docstring)."""
    # 1/(e^x - 1) by expm1; a huge logarithm contributes nothing
    inv = sum(1.0 / math.expm1(x) if x < 700.0 else 0.0 for x in (sparse, array))
    return math.log1p(1.0 / inv)


def drag_coefficients(
    model: str,
    viscosity: float,
    length: float,
    radius: float,
    area: float,
    k_perp: float,
    phi: float,
) -> tuple[float, float]:
    """(zeta_perp, zeta_par) [Pa s] of one hair under the drag ``model`` (module docstring):
    viscosity eta [Pa s], hair length L and radius a [m], wall area per hair A [m^2], the
    array's transverse permeability k_perp [m^2] and its packing fraction phi [-]."""
    model = check_choice(model, "drag", DRAG_MODELS)
    lg = math.log(2.0 * length / radius)
    sparse = (lg + 0.5, lg - 0.5)
    k_par = parallel_permeability(radius, phi)
    array = (4.0 * math.pi * k_perp / area, 2.0 * math.pi * k_par / area)
    if model == "sparse":
        logs = sparse
    elif model == "array":
        logs = array
    else:
        logs = (_cut(sparse[0], array[0]), _cut(sparse[1], array[1]))
    return 4.0 * math.pi * viscosity / logs[0], 2.0 * math.pi * viscosity / logs[1]


def _series_slopes(phi: float) -> tuple[float, float]:
    """d/d ln phi of the array's logarithms Lambda_perp = S_perp(phi)/2 and Lambda_par =
    S_par(phi)/2 (Drummond & Tahir's series, as in :func:`drag_coefficients`: 4 pi k_perp/A
    = S_perp/2 and 2 pi k_par/A = S_par/2 with A = pi a^2/phi)."""
    b = 1.2758
    d_perp = (
        -1.0 / phi + 2.0 - phi - 4.0 * 0.739 * phi**3
        + 2.534 * (5.0 * phi**4 * (1.0 + b * phi) - b * phi**5) / (1.0 + b * phi) ** 2
    )  # fmt: skip
    d_par = -1.0 / phi + 2.0 - phi - 6.0 * 0.0018 * phi**5
    return 0.5 * phi * d_perp, 0.5 * phi * d_par


def _cut_slopes(sparse: float, array: float) -> tuple[float, float]:
    """(d/d sparse, d/d array) of :func:`_cut`: with u = sum 1/(e^x - 1) and
    cut = ln(1 + 1/u), d cut/dx = e^x/((e^x - 1)^2 u (u + 1))."""
    inv = sum(1.0 / math.expm1(x) if x < 700.0 else 0.0 for x in (sparse, array))
    out = []
    for x in (sparse, array):
        if x >= 700.0:  # a huge logarithm contributes nothing, nor does its change
            out.append(0.0)
            continue
        em = math.expm1(x)
        out.append((em + 1.0) / (em * em * inv * (inv + 1.0)))
    return out[0], out[1]


def drag_logarithm_slopes(
    model: str, length: float, radius: float, area: float, k_perp: float, phi: float
) -> dict[str, tuple[float, float]]:
    """The derivatives of the drag logarithms (Lambda_perp, Lambda_par) of
    :func:`drag_coefficients` (zeta_perp = 4 pi eta/Lambda_perp, zeta_par = 2 pi eta/
    Lambda_par) in their two variables, ``{"log_slenderness": (dLp, dLq), "log_phi": (...)}``:
    d/d ln(2L/a) (the sparse part) and d/d ln phi (the array part), exact (the chain rule
    through the crossover's harmonic cut), and the logarithms themselves under ``"value"``.
    Inputs as :func:`drag_coefficients`', checked by the caller."""
    model = check_choice(model, "drag", DRAG_MODELS)
    lg = math.log(2.0 * length / radius)
    sparse = (lg + 0.5, lg - 0.5)
    k_par = parallel_permeability(radius, phi)
    array = (4.0 * math.pi * k_perp / area, 2.0 * math.pi * k_par / area)
    d_array = _series_slopes(phi)
    if model == "sparse":
        return {"value": sparse, "log_slenderness": (1.0, 1.0), "log_phi": (0.0, 0.0)}
    if model == "array":
        return {"value": array, "log_slenderness": (0.0, 0.0), "log_phi": d_array}
    cuts = [_cut_slopes(sparse[i], array[i]) for i in (0, 1)]
    return {
        "value": (_cut(sparse[0], array[0]), _cut(sparse[1], array[1])),
        "log_slenderness": (cuts[0][0], cuts[1][0]),
        "log_phi": (cuts[0][1] * d_array[0], cuts[1][1] * d_array[1]),
    }
