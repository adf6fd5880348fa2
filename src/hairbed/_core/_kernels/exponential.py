"""An exponential Rosenbrock integrator for the ringing pillar (issue 30, theory.md §14).

The semi-discrete pillar y' = f(t, y) of ``dynamics.pillar_rates`` is linearised afresh at
the start (t_n, y_n) of every step, with the exact Jacobian J_n and the drives' rate
v_n = df/dt there:

    y' = f_n + J_n (y - y_n) + v_n (t - t_n) + g_n(t, y),
    g_n = f(t, y) - f_n - J_n (y - y_n) - v_n (t - t_n) = O(|y - y_n|^2 + |t - t_n|^2),

so the linear ringing about the current state, in every mode and at any frequency, is
exact (matrix functions of h J_n), and only the remainder g_n, second order in the step's
change, is approximated. The scheme is exprb43 of M. Hochbruck, A. Ostermann and
J. Schweitzer, Exponential Rosenbrock-type methods, SIAM J. Numer. Anal. 47, 786-803 (2009)
(order 4, an embedded order-3 solution, two evaluations of the remainder): with
phi_0(z) = e^z, phi_{k+1}(z) = (phi_k(z) - 1/k!)/z and the time carried as an extra unknown
(J~ = [[J_n, v_n], [0, 0]], F~ = (f_n, 1)),

    U_2 = y_n + (h/2) phi_1(h J~/2) F~,                    D_2 = g_n(t_n + h/2, U_2),
    U_3 = y_n + h phi_1(h J~) F~ + h phi_1(h J_n) D_2,      D_3 = g_n(t_n + h, U_3),
    y_{n+1} = y_n + h phi_1(h J~) F~ + h phi_3(h J_n) (16 D_2 - 2 D_3)
              + h phi_4(h J_n) (-48 D_2 + 12 D_3),

the last term the error estimate. These weights integrate exactly the cubic remainder
g(s) = d_2 (s/h)^2 + d_3 (s/h)^3 (d_2 = 8 D_2 - D_3, d_3 = 2 D_3 - 8 D_2) that vanishes with
its slope at the step's start and passes through D_2 and D_3; the dense output is the same
cubic integrated to any point of the step, the exact solution of a linear system with
constant coefficients carried by four more unknowns (its matrix exponential).

The matrix functions are dense (2 (N - 1) + 1 unknowns): the matrix is balanced by a
diagonal similarity of powers of two (Parlett and Reinsch; the Chebyshev rows make it far
from normal, ||J||_1 = 2e6 against a spectral radius of 900 at N = 12), scaled by 2^-s, its
phi_4 summed there by a Taylor polynomial of degree 5 nb - 1 evaluated by Paterson and
Stockmeyer's scheme (the powers X^2 .. X^5, then nb - 1 products in X^5), phi_3 .. phi_0 by
phi_k = 1/k! + X phi_(k+1), and brought back by the doubling formulas
phi_k(2 z) = 2^-k (phi_0(z) phi_k(z) + sum_{j=1}^k phi_j(z)/(k - j)!) (B. Skaflestad and
W. M. Wright, Appl. Numer. Math. 59, 783-799, 2009); phi_1(h J~/2) is the last level but one.
The scaling follows A. H. Al-Mohy and N. J. Higham, SIAM J. Matrix Anal. Appl. 31, 970-989
(2009), Theorem 4.2: a power series' tail sum_{i > m} c_i X^i is bounded by that of |c_i|
at alpha = min_p max(d_p, d_(p+1)), d_j = ||X^j||_1^(1/j) (p = 1 .. 4, p (p - 1) <= m + 1),
which for the non-normal Jacobian is 4 to 5 times below ||X||_1 (d_4 = 1590 h against
||h J||_1 = 6900 h, balanced): s and nb (3 .. 7) are those of least work (a doubling costs
about six products) with alpha 2^-s <= theta_nb, theta_nb the largest x at which every
phi_k's (k = 0 .. 4) Taylor remainder, sum_{i > 5 nb + 3 - k} x^i/(i + k)!, is below
2^-53/k! (``_PHI_THETAS``; the exponential of the dense output likewise, degree 5 nb - 1,
``_EXP_THETAS``). At a typical step (h = 0.01 T, N = 12) this is two doublings where the
1-norm and a degree-15 series at 1/2 took eight.

Error norm: every component, err/(atol + rtol |y|) (weighing the angles alone lets the fast
modes' rates drift and the slow mode's phase with them: a floor of 1.2e-6 in the tip at any
tolerance); the step by Gustafsson's PI control,
0.9 err_n^(-0.175) err_(n-1)^(0.1) within [0.2, 5] (0.9 err^(-1/4) after a rejection).

With the drag every mode of the ringing pillar decays at about 1/(2 mu): a true step rings
in all of them for hundreds of T. The steps follow the remainder (the modes' nonlinear
interaction), not the ringing.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import kernel
from .dynamics import _lowest_cos, pillar_rates, tip_speed, workspace
from .rod_motion import drive_value

__all__ = ["integrate_exponential", "phi_matrices", "expm_augmented"]

#: Status codes (those of ``dynamics.integrate_pillar``).
_OK = 0
_OUTSIDE = -8
_MAXSTEPS = -2
_SMALL = -3
_JUMP = -9
#: Paterson and Stockmeyer's block: the powers X^1 .. X^5 of the scaled matrix, the Taylor
#: polynomial in nb blocks of five coefficients (degree 5 nb - 1, nb = 3 .. _NB).
_R = 5
_NB = 7
#: phi_4's Taylor coefficients 1/(j + 4)! and the exponential's 1/j!, j = 0 .. 5 _NB - 1.
_PHI_COEF = np.array([1.0 / math.factorial(j + 4) for j in range(_R * _NB)])
_EXP_COEF = np.array([1.0 / math.factorial(j) for j in range(_R * _NB)])
#: theta_nb (index nb): the largest x with max_k k! sum_{i > 5 nb + 3 - k} x^i/(i + k)! <= 2^-53
#: (phi_0 .. phi_4 from phi_4 of degree 5 nb - 1; mpmath at 40 digits, bisection), and for
#: the exponential alone sum_{i > 5 nb - 1} x^i/i! <= 2^-53 (tests/test_dynamics_exponential.py
#: checks both tables).
_PHI_THETAS = np.array(
    [0.0, 0.0, 0.0, 0.95925330888514256, 2.0941243196094493, 3.2752135590741406,
     4.5755269456515098, 5.9777666132527752]
)  # fmt: skip
_EXP_THETAS = np.array(
    [0.0, 0.0, 0.0, 0.55349051569385327, 1.318781226194848, 2.3324673844012391,
     3.5255637669883704, 4.8487666817790796]
)  # fmt: skip
#: The cost of one doubling of the phi functions (four products and the sums) and of one
#: squaring of the exponential, in matrix products.
_PHI_DOUBLING = 6.0
_EXP_SQUARING = 1.1


@kernel
def _balance(a, p, d):
    """Balance a[:p, :p] in place by a diagonal similarity of powers of two, a <- D^-1 a D
    (the rows and columns of each index of comparable 1-norms: Parlett and Reinsch, as
    LAPACK's dgebal without permutations); d[:p] receives D's diagonal."""
    for i in range(p):
        d[i] = 1.0
    done = False
    sweeps = 0
    while not done and sweeps < 40:
        done = True
        sweeps += 1
        for i in range(p):
            c = 0.0
            r = 0.0
            for k in range(p):
                if k != i:
                    c += abs(a[k, i])
                    r += abs(a[i, k])
            if c == 0.0 or r == 0.0:
                continue
            g = r / 2.0
            f = 1.0
            s = c + r
            while c < g:
                f *= 2.0
                c *= 4.0
            g = r * 2.0
            while c > g:
                f /= 2.0
                c /= 4.0
            if (c + r) / f < 0.95 * s:
                done = False
                d[i] *= f
                for k in range(p):
                    a[i, k] /= f
                    a[k, i] *= f


@kernel
def _norm1(a, p):
    """||a[:p, :p]||_1, the largest column sum."""
    big = 0.0
    for k in range(p):
        acc = 0.0
        for i in range(p):
            acc += abs(a[i, k])
        big = max(big, acc)
    return big


@kernel
def _scaled_powers(a, p, thetas, cost, smin, x, pw):
    """The scaling 2^-s and the number of blocks nb of least work ((nb - 1) + cost s
    products) with alpha 2^-s <= thetas[nb], s >= smin (module docstring); x = a 2^-s and
    pw[j] = x^(j + 2), j = 0 .. 3. Returns (s, nb).

    The powers are formed at a first scaling 2^-s0 with ||a 2^-s0||_1 <= thetas[_NB] (no
    overflow) and brought to 2^-s by exact powers of two."""
    top = thetas[_NB]
    big = _norm1(a, p)
    s0 = 0
    if big > top:  # (at most 1100 halvings: the largest finite norm)
        s0 = int(math.ceil(math.log2(min(big, 1e308) / top)))
    sc = 0.5**s0
    for i in range(p):
        for k in range(p):
            x[i, k] = a[i, k] * sc
    np.dot(x, x, pw[0])
    for j in range(1, _R - 1):
        np.dot(pw[j - 1], x, pw[j])
    # alpha = min_p max(d_p, d_(p+1)), d_j = ||x^j||_1^(1/j), p = 1 .. 4 (d_1 >= d_2 bound)
    alpha = _norm1(x, p)
    dprev = _norm1(pw[0], p) ** 0.5
    for j in range(1, _R - 1):
        dj = _norm1(pw[j], p) ** (1.0 / (j + 2.0))
        alpha = min(alpha, max(dprev, dj))
        dprev = dj
    best = math.inf
    s = smin
    nb = _NB
    for b in range(3, _NB + 1):
        sb = smin
        if alpha > 0.0:
            sb = max(smin, s0 + int(math.ceil(math.log2(alpha / thetas[b]))))
        work = (b - 1.0) + cost * sb
        if work < best:
            best = work
            s = sb
            nb = b
    if s != s0:
        c = 2.0 ** (s0 - s)
        for i in range(p):
            for k in range(p):
                x[i, k] *= c
        ck = c
        for j in range(_R - 1):
            ck *= c
            w = pw[j]
            for i in range(p):
                for k in range(p):
                    w[i, k] *= ck
    return s, nb


@kernel
def _ps_poly(coef, nb, p, x, pw, acc, buf, res):
    """res = sum_{j < 5 nb} coef[j] x^j by Paterson and Stockmeyer: the blocks
    B_i = sum_{l < 5} coef[5 i + l] x^l in the powers x, pw[0 .. 2] = x^2 .. x^4, by Horner in
    pw[3] = x^5 (nb - 1 products). acc, buf: work (res may be either)."""
    cur = acc
    nxt = buf
    for blk in range(nb - 1, -1, -1):
        if blk == nb - 1:
            for i in range(p):
                for k in range(p):
                    cur[i, k] = 0.0
        else:
            np.dot(pw[_R - 2], cur, nxt)
            cur, nxt = nxt, cur
        b0 = blk * _R
        c1 = coef[b0 + 1]
        for i in range(p):
            for k in range(p):
                cur[i, k] += c1 * x[i, k]
            cur[i, i] += coef[b0]
        for ll in range(2, _R):
            cl = coef[b0 + ll]
            w = pw[ll - 2]
            for i in range(p):
                for k in range(p):
                    cur[i, k] += cl * w[i, k]
    for i in range(p):
        for k in range(p):
            res[i, k] = cur[i, k]


@kernel
def phi_matrices(a, kmax, out, half, tmp, full=True):
    """out[k] = phi_k(a) for k = 0 .. 4 (kmax = 4; a square, float64) and half =
    phi_1(a/2): phi_4's Taylor polynomial at a/2^s by Paterson and Stockmeyer (s >= 1 and
    its degree by the scaling of Al-Mohy and Higham, module docstring), phi_3 .. phi_0 by
    phi_k = 1/k! + X phi_(k+1), then s doublings
    phi_k(2 z) = 2^-k (phi_0 phi_k + sum_{j=1}^k phi_j/(k - j)!) (Skaflestad and Wright).
    Where ``full`` is False the last doubling skips phi_0 and phi_2 (out[0] and out[2] are
    left at a/2: the step needs phi_1, phi_3 and phi_4 alone). tmp: a work array of three
    matrices of a's shape (out[0 .. 3] hold the powers meanwhile). a is not balanced here
    (see ``_balance``)."""
    if kmax != 4:
        raise ValueError("phi_matrices: kmax must be 4")
    p = a.shape[0]
    x = tmp[0]
    pw = out[: _R - 1]
    s, nb = _scaled_powers(a, p, _PHI_THETAS, _PHI_DOUBLING, 1, x, pw)
    _ps_poly(_PHI_COEF, nb, p, x, pw, tmp[1], tmp[2], out[4])
    for kk in range(3, -1, -1):  # phi_k = 1/k! + x phi_{k+1}
        np.dot(x, out[kk + 1], out[kk])
        ck = 1.0 / math.gamma(kk + 1.0)
        for i in range(p):
            out[kk, i, i] += ck
    inv = np.empty(5)
    w = tmp[1]
    for level in range(s):
        last = level == s - 1
        if last:
            for i in range(p):
                for k in range(p):
                    half[i, k] = out[1, i, k]
        for kk in range(4, 0, -1):  # phi_k(2z) from the phi_j(z), j <= k, in place
            if last and not full and kk == 2:
                continue
            np.dot(out[0], out[kk], w)
            fac = 0.5**kk
            for j in range(1, kk + 1):
                inv[j] = fac / math.gamma(kk - j + 1.0)
            ok = out[kk]
            for i in range(p):  # contiguous inner loops (they vectorise)
                for k in range(p):
                    ok[i, k] = fac * w[i, k] + inv[kk] * ok[i, k]
            for j in range(1, kk):
                oj = out[j]
                cj = inv[j]
                for i in range(p):
                    for k in range(p):
                        ok[i, k] += cj * oj[i, k]
        if last and not full:
            break
        np.dot(out[0], out[0], w)
        for i in range(p):
            for k in range(p):
                out[0, i, k] = w[i, k]


@kernel
def expm_augmented(a, e, tmp):
    """e = exp(a) (a square; balanced in the work, undone on the result): the Taylor
    polynomial of the scaled, balanced matrix by Paterson and Stockmeyer and s squarings,
    s and the degree by the scaling of Al-Mohy and Higham (module docstring). tmp: work
    (8, p, p) (a smaller one is replaced by a fresh array)."""
    p = a.shape[0]
    if tmp.shape[0] >= 8:
        w = tmp
    else:
        w = np.empty((8, p, p))
    bal = w[0]
    d = w[7, 0]
    for i in range(p):
        for k in range(p):
            bal[i, k] = a[i, k]
    _balance(bal, p, d)
    x = w[1]
    pw = w[2:6]
    s, nb = _scaled_powers(bal, p, _EXP_THETAS, _EXP_SQUARING, 0, x, pw)
    _ps_poly(_EXP_COEF, nb, p, x, pw, w[0], w[6], w[6])
    cur = w[6]
    nxt = e
    for _ in range(s):
        np.dot(cur, cur, nxt)
        cur, nxt = nxt, cur
    if s % 2 == 0:  # (the last square is in e where s is odd)
        for i in range(p):
            for k in range(p):
                e[i, k] = cur[i, k]
    for i in range(p):  # undo the balancing: D e D^-1
        for k in range(p):
            e[i, k] *= d[i] / d[k]


@kernel
def _apply(mat, d, x, p, out, wv):
    """out = D mat D^-1 x (the matrix function of the unbalanced matrix applied to x); wv:
    work of p."""
    for k in range(p):
        wv[k] = x[k] / d[k]
    for i in range(p):
        acc = 0.0
        for k in range(p):
            acc += mat[i, k] * wv[k]
        out[i] = d[i] * acc


@kernel
def _drive_rate(t, h, drives, tabs):
    """(dLambda/dt, dP/dt) at t by one-sided second-order differences over delta =
    max(1e-5 h, 1e-9 (1 + |t|)) (the drives are piecewise smooth; forwards, as the step
    goes), and delta."""
    dl = max(1e-5 * h, 1e-9 * (1.0 + abs(t)))
    out = np.zeros(2)
    for r in range(2):
        v0 = drive_value(int(drives[r, 0]), drives[r, 1:], tabs[2 * r], tabs[2 * r + 1], t)
        v1 = drive_value(int(drives[r, 0]), drives[r, 1:], tabs[2 * r], tabs[2 * r + 1], t + dl)
        v2 = drive_value(
            int(drives[r, 0]), drives[r, 1:], tabs[2 * r], tabs[2 * r + 1], t + 2.0 * dl
        )
        out[r] = (-3.0 * v0 + 4.0 * v1 - v2) / (2.0 * dl)
    return out, dl


@kernel
def _dense_matrix(m, h, fn, v, d2, d3, tau, aug, arg, e, tmp):
    """e = exp(tau A) for the step's dense output: A acts on (u - y_n, 1, s/h, (s/h)^2,
    (s/h)^3) with u' = f_n + J_n (u - y_n) + v_n h (s/h) + d_2 (s/h)^2 + d_3 (s/h)^3 and
    d/ds (s/h)^j = (j/h) (s/h)^(j-1); aug[:m, :m] holds J_n already. arg: work of e's
    shape; tmp: (8, m + 4, m + 4) work."""
    for i in range(m):
        aug[i, m] = fn[i]
        aug[i, m + 1] = v[i] * h
        aug[i, m + 2] = d2[i]
        aug[i, m + 3] = d3[i]
    for i in range(m, m + 4):
        for k in range(m + 4):
            aug[i, k] = 0.0
    aug[m + 1, m] = 1.0 / h
    aug[m + 2, m + 1] = 2.0 / h
    aug[m + 3, m + 2] = 3.0 / h
    for i in range(m + 4):
        for k in range(m + 4):
            arg[i, k] = tau * aug[i, k]
    expm_augmented(arg, e, tmp)


@kernel
def _dense_at(m, h, fn, v, c2, c3, tau, y, aug, arg, e, tmp, out):
    """out = u(t_n + tau), the step's dense output (``_dense_matrix``)."""
    _dense_matrix(m, h, fn, v, c2, c3, tau, aug, arg, e, tmp)
    for i in range(m):
        out[i] = y[i] + e[i, m]


@kernel
def integrate_exponential(
    y0,
    t_start,
    t_eval,
    rtol,
    atol,
    h_start,
    max_steps,
    num,
    dd,
    ii,
    srow,
    theta0,
    gamma,
    chi,
    mu,
    prof,
    drives,
    tabs,
    y_out,
    counts,
    jump_speed=0.0,
):
    """exprb43 (module docstring) on y' = f(t, y) of ``dynamics.pillar_rates`` from
    (t_start, y0), writing y at every t_eval (sorted, >= t_start) into y_out by the dense
    output.

    Error norm: the root mean square over the components of err/(atol + rtol max(|y_n|,
    |y_n+1|)), err the difference of the order-4 and order-3 solutions. Events, located
    by bisection on the dense output, stop the run as in ``dynamics.integrate_pillar``: a
    node reaching |theta| = pi/2 (status -8); where
    ``jump_speed`` > 0, the tip's speed reaching it (-9). Returns (status, t_end): 0, -8,
    -9, -2 after max_steps steps, -3 for a step below 1e-14 (t + 1) or failed rates.
    counts: steps, accepted, rejected, f evaluations, Jacobians, matrix functions (the
    phi functions of a step, the exponentials of the dense output)."""
    m = y0.size
    n_eval = t_eval.size
    p = m + 1  # with the time
    ws = workspace(num)
    th_tmp = np.empty(num + 1)
    y = np.empty(m)
    y1 = np.empty(m)
    yt = np.empty(m)
    fn = np.empty(m)
    f = np.empty(m)
    fa = np.empty(m)
    fb = np.empty(m)
    v = np.zeros(m)
    jac = np.zeros((m, m))
    jdummy = np.zeros((m, m))
    jt = np.zeros((p, p))  # h J~, balanced
    dbal = np.empty(p)
    phis = np.empty((5, p, p))
    half = np.empty((p, p))
    ptmp = np.empty((3, p, p))
    x = np.zeros(p)
    xw = np.empty(p)
    z = np.empty(p)
    z2 = np.empty(p)
    lin1 = np.empty(m)  # h phi_1(h J~) F~ (the y part)
    d2 = np.empty(m)
    d3 = np.empty(m)
    c2 = np.empty(m)
    c3 = np.empty(m)
    err = np.empty(m)
    q = m + 4
    aug = np.zeros((q, q))
    emat = np.empty((q, q))
    estep = np.empty((q, q))
    earg = np.empty((q, q))
    etmp = np.zeros((8, q, q))
    zc = np.empty(q)
    zn = np.empty(q)
    for k in range(m):
        y[k] = y0[k]
    t = t_start
    t_end = t_eval[n_eval - 1]
    h = min(h_start, t_end - t) if t_end > t else 0.0
    nxt = 0
    while nxt < n_eval and t_eval[nxt] <= t:
        for k in range(m):
            y_out[nxt, k] = y[k]
        nxt += 1
    if nxt >= n_eval:
        return _OK, t
    pr = (num, dd, ii, srow, theta0, gamma, chi, mu, prof, drives, tabs)
    steps = 0
    rejected = False
    en_prev = 1.0
    fresh = True  # f_n, J_n, v_n to be taken at (t, y)
    while nxt < n_eval:
        if fresh:
            if not pillar_rates(t, y, True, *pr, fn, jac, ws):
                return _SMALL, t
            counts[3] += 1
            counts[4] += 1
            rate, dl = _drive_rate(t, h, drives, tabs)
            for i in range(m):
                v[i] = 0.0
            if rate[0] != 0.0 or rate[1] != 0.0:  # df/dt: f is affine in the drives
                if not pillar_rates(t + dl, y, False, *pr, fa, jdummy, ws):
                    return _SMALL, t
                if not pillar_rates(t + 2.0 * dl, y, False, *pr, fb, jdummy, ws):
                    return _SMALL, t
                counts[3] += 2
                for i in range(m):
                    v[i] = (-3.0 * fn[i] + 4.0 * fa[i] - fb[i]) / (2.0 * dl)
            for i in range(m):
                for k in range(m):
                    aug[i, k] = jac[i, k]
            fresh = False
        steps += 1
        counts[0] += 1
        if steps > max_steps:
            return _MAXSTEPS, t
        if h < 1e-14 * (abs(t) + 1.0):
            return _SMALL, t
        # the phi functions of h J~ (balanced); a non-finite linearisation ends the run
        finite = True
        for i in range(m):
            if not (math.isfinite(fn[i]) and math.isfinite(v[i])):
                finite = False
            for k in range(m):
                if not math.isfinite(jac[i, k]):
                    finite = False
        if not finite:
            return _SMALL, t
        for i in range(m):
            for k in range(m):
                jt[i, k] = h * jac[i, k]
            jt[i, m] = h * v[i]
        for k in range(p):
            jt[m, k] = 0.0
        _balance(jt, p, dbal)
        phi_matrices(jt, 4, phis, half, ptmp, False)
        counts[5] += 1
        good = True
        # stage 2: U_2 = y_n + (h/2) phi_1(h J~/2) F~
        for i in range(m):
            x[i] = fn[i]
        x[m] = 1.0
        _apply(half, dbal, x, p, z, xw)
        for i in range(m):
            yt[i] = y[i] + 0.5 * h * z[i]
        good = pillar_rates(t + 0.5 * h, yt, False, *pr, f, jdummy, ws)
        if good:
            for i in range(m):
                acc = f[i] - fn[i] - 0.5 * h * v[i]
                for k in range(m):
                    acc -= jac[i, k] * (yt[k] - y[k])
                d2[i] = acc
            # stage 3: U_3 = y_n + h phi_1(h J~) (F~ + D_2)
            _apply(phis[1], dbal, x, p, z, xw)
            for i in range(m):
                lin1[i] = h * z[i]
                x[i] = d2[i]
            x[m] = 0.0
            _apply(phis[1], dbal, x, p, z, xw)
            for i in range(m):
                yt[i] = y[i] + lin1[i] + h * z[i]
            good = pillar_rates(t + h, yt, False, *pr, f, jdummy, ws)
        counts[3] += 2
        en = 1e10
        if good:
            for i in range(m):
                acc = f[i] - fn[i] - h * v[i]
                for k in range(m):
                    acc -= jac[i, k] * (yt[k] - y[k])
                d3[i] = acc
                x[i] = 16.0 * d2[i] - 2.0 * d3[i]
            x[m] = 0.0
            _apply(phis[3], dbal, x, p, z, xw)
            for i in range(m):
                x[i] = -48.0 * d2[i] + 12.0 * d3[i]
            _apply(phis[4], dbal, x, p, z2, xw)
            for i in range(m):
                err[i] = h * z2[i]
                y1[i] = y[i] + lin1[i] + h * z[i] + err[i]
            en = 0.0
            for i in range(m):
                sc = atol + rtol * max(abs(y[i]), abs(y1[i]))
                en += (err[i] / sc) ** 2
            en = math.sqrt(en / m)
            if not math.isfinite(en):
                en = 1e10
        # Gustafsson's PI control (k = 4): the last accepted error damps the growth
        fac = min(5.0, max(0.2, 0.9 * max(en, 1e-12) ** (-0.175) * en_prev**0.1))
        if en > 1.0:
            fac = min(5.0, max(0.2, 0.9 * max(en, 1e-12) ** (-0.25)))
            rejected = True
            counts[2] += 1
            h *= min(fac, 0.5) if not good else fac
            continue
        counts[1] += 1
        # the dense output's cubic remainder: d_2 = 8 D_2 - D_3, d_3 = 2 D_3 - 8 D_2
        for i in range(m):
            c2[i] = 8.0 * d2[i] - d3[i]
            c3[i] = 2.0 * d3[i] - 8.0 * d2[i]
        t_new = t + h
        t_stop = t_new
        status = _OK
        if _lowest_cos(y1, num, theta0, srow, th_tmp) <= 0.0:
            lo = 0.0
            hi = 1.0
            for _ in range(60):
                mid = 0.5 * (lo + hi)
                _dense_at(m, h, fn, v, c2, c3, mid * h, y, aug, earg, emat, etmp, yt)
                counts[5] += 1
                if _lowest_cos(yt, num, theta0, srow, th_tmp) <= 0.0:
                    hi = mid
                else:
                    lo = mid
            t_stop = t + hi * h
            status = _OUTSIDE
        if jump_speed > 0.0:
            tau = (t_stop - t) / h
            if tau < 1.0:
                _dense_at(m, h, fn, v, c2, c3, tau * h, y, aug, earg, emat, etmp, yt)
                counts[5] += 1
            else:
                for k in range(m):
                    yt[k] = y1[k]
            vel = tip_speed(t_stop, yt, *pr, f, jdummy, ws, th_tmp)
            counts[3] += 1
            if not vel < jump_speed:
                lo = 0.0
                hi = tau
                for _ in range(60):
                    mid = 0.5 * (lo + hi)
                    _dense_at(m, h, fn, v, c2, c3, mid * h, y, aug, earg, emat, etmp, yt)
                    counts[5] += 1
                    vel = tip_speed(t + mid * h, yt, *pr, f, jdummy, ws, th_tmp)
                    counts[3] += 1
                    if not vel < jump_speed:
                        hi = mid
                    else:
                        lo = mid
                t_stop = t + hi * h
                status = _JUMP
        # the outputs in the step: exp(tau A) from the step's start, then exp(delta A)
        # from one output to the next (reused while the outputs are evenly spaced)
        last_tau = 0.0
        last_gap = -1.0
        for k in range(q):
            zc[k] = 0.0
        zc[m] = 1.0
        while nxt < n_eval and t_eval[nxt] <= t_stop:
            tau = t_eval[nxt] - t
            if tau >= h and status == _OK:
                for k in range(m):
                    y_out[nxt, k] = y1[k]
                nxt += 1
                continue
            gap = tau - last_tau
            if abs(gap - last_gap) > 1e-13 * (abs(t) + h):
                _dense_matrix(m, h, fn, v, c2, c3, gap, aug, earg, estep, etmp)
                counts[5] += 1
                last_gap = gap
            for i in range(q):
                acc = 0.0
                for k in range(q):
                    acc += estep[i, k] * zc[k]
                zn[i] = acc
            for i in range(q):
                zc[i] = zn[i]
            for k in range(m):
                y_out[nxt, k] = y[k] + zc[k]
            last_tau = tau
            nxt += 1
        if status != _OK:
            return status, t_stop
        for k in range(m):
            y[k] = y1[k]
        t = t_new
        fresh = True
        if rejected:
            fac = min(fac, 1.0)
        rejected = False
        en_prev = max(en, 1e-4)
        h = h * fac
        if t_end - t > 0.0:
            h = min(h, t_end - t)
        if t_end - t <= 1e-14 * (abs(t) + 1.0):
            while nxt < n_eval:
                for k in range(m):
                    y_out[nxt, k] = y[k]
                nxt += 1
    return _OK, t
