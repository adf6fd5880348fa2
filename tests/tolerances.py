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
