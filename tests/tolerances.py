"""The one place for test tolerances."""

#: Agreement with the high-precision (mpmath) reference: relative, and absolute near zero.
RTOL = 1e-12
ATOL = 1e-12
#: Identities that hold exactly for every returned solution (checked in double precision).
IDENTITY_RTOL = 1e-10
IDENTITY_ATOL = 1e-10
#: Agreement with central finite differences of the code's own inversion (step ~1e-6 of the
#: scale: truncation ~1e-12, rounding ~1e-10 relative, with a margin for slopes near folds).
FINITE_DIFFERENCE_RTOL = 1e-6
#: solve_loaded (issue 20) at pi = 0 against the closed form hairbed.solve: absolute on h1, x1,
#: theta1, relative to max(1, |theta'(0)|) on the base curvature.
LOADED_CLOSED_FORM_ATOL = 1e-12
#: The base-moment identity theta'(0) = W h1 + Pi h1^2/2 on every state solve_loaded returns,
#: relative to max(1, |theta'(0)|).
LOADED_IDENTITY_RTOL = 1e-12
#: The small-load limit x1 = W/3 + Pi/8: the fitted slope of log(remainder/x1) against
#: log(load) is 2 within this.
LOADED_LIMIT_SLOPE_ATOL = 0.05
#: The error estimate is honest: |value(N) - value(2N)| <= this times the sum of the two
#: estimates (each bounds its own error).
LOADED_ESTIMATE_MARGIN = 1.0
#: Against scipy.integrate.solve_bvp at tol 1e-12 (its own error is the larger part).
LOADED_BVP_ATOL = 1e-8
#: Against the independent mpmath reference tests/data/loaded_mpmath.json (issue 20 target).
LOADED_REFERENCE_ATOL = 1e-10
#: The isolated pillar (issue 21) against the mpmath reference of generate_pillar.py: every
#: value within this (relative above 1), forward, inverse and round trip.
PILLAR_REFERENCE_ATOL = 1e-10
#: The pillar with its load concentrated at the tip against the tip-loaded elastica: the
#: error must fall at least this factor when the profile's concentration doubles (O(1/p)).
PILLAR_CONCENTRATION_RATE = 1.8
#: Derivatives of loaded states (implicit differentiation of the collocation) against central
#: differences of solve_loaded with Richardson extrapolation (truncation ~h^4 = 1e-12, rounding
#: ~1e-13/h = 1e-10 at h = 1e-3), relative to max(1, abs(value)).
LOADED_DERIVATIVE_FD_RTOL = 1e-8
#: Against the mpmath central differences tests/data/loaded_derivatives_mpmath.json (each
#: accurate to ~1e-18), relative to max(1, abs(value)): the collocation's own error.
LOADED_DERIVATIVE_REFERENCE_RTOL = 1e-9
#: Derivatives of pillar states (implicit differentiation of the collocation) against central
#: differences of solve_pillar with Richardson extrapolation (truncation ~h^4, rounding
#: ~1e-14/h), relative to max(1e-3, abs(value)) (the derivatives' own scale is O(1e-2)).
PILLAR_DERIVATIVE_FD_RTOL = 1e-8
#: Against the mpmath central differences tests/data/pillar_derivatives_mpmath.json (each
#: accurate to ~1e-24), relative to max(1, abs(value)): the collocation's own error (measured
#: 4.9e-13 at worst over 198 derivatives).
PILLAR_DERIVATIVE_REFERENCE_RTOL = 1e-11
#: A pillar calibration's exact Jacobian (derivatives_at through the SI scaling) against
#: central differences of model_tip_deflection at relative step 1e-5 (truncation ~1e-10,
#: rounding ~1e-16/1e-5), relative to the column's largest entry.
PILLAR_JACOBIAN_FD_RTOL = 1e-8
#: Spalding's law of the wall (issue 31): hairbed.spalding_u_plus against mpmath's root of the
#: formula, relative (the issue's target 1e-12).
WALL_LAW_RTOL = 1e-12
#: The wall-law profile U(z) = u+(L+ z)/L+ as the collocation takes it (Chebyshev
#: coefficients) against mpmath, absolute (U <= 1).
WALL_LAW_PROFILE_ATOL = 1e-13
#: Linear pillar dynamics (issue 30) against the Euler-Bernoulli cantilever's Krylov-function
#: transfer functions and eigenvalues in mpmath, relative (the issue's target 1e-10).
DYNAMICS_LINEAR_RTOL = 1e-10
#: The nonlinear pillar in time (issue 30): a constant drive's end state against the static
#: solver, relative above 1 (the issue's target 1e-10).
DYNAMICS_STEADY_ATOL = 1e-10
#: The overdamped energy balance d(elastic)/dt = input - dissipation of the collocation,
#: relative to the largest input power (the semi-discretisation's own mismatch, measured
#: 6e-11 at N = 32 during and after a ramp; at the impulsive start of a ramp, where the
#: boundary layers of the rate are not resolved, 1e-7).
DYNAMICS_ENERGY_RTOL = 1e-9
#: An element of an array-valued Pillar against the scalar pillar, relative: the pillar core's
#: batched solves differ from one element's in the last bits (it chains neighbouring
#: elements of the same theta0, drag ratio and profile, as for an array of stresses on one
#: pillar, whose elements differ alike); measured up to 8e-14 (sublayer) and 3e-13 (wall law),
#: the solver's own tolerance being 1e-12.
ARRAY_MODEL_CHAINED_RTOL = 1e-11
