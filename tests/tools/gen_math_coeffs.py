#!/usr/bin/env python3
"""gen_math_coeffs.py - derive the constants, tables and polynomial coefficients
of src/base/math_*.c.

Everything here is computed from first principles with mpmath (apt-get install
python3-mpmath) at 120 decimal digits:

  * constants (pi/2, ln2/64, 1/ln10, ...) split into a head with few enough
    significant bits that products with small integers are exact, and a tail;
  * tables: 2^(j/N) as head+tail, log(1/c_j) as head+tail for reciprocals c_j
    with few significant bits, atan(j/16) as head+tail, the bits of 2/pi;
  * polynomials: a weighted minimax fit computed with the Remez exchange
    algorithm below (linear system on n+1 reference points, extrema of the
    weighted error located on a dense Chebyshev grid and refined by golden
    section search), then rounded to the target format. The error of the
    rounded polynomial is re-measured on a dense grid and printed as log2.

Usage: python3 tests/tools/gen_math_coeffs.py > /tmp/coeffs.txt
The output is C text pasted into src/base/math_trig.c and src/base/math_explog.c.
Nothing is copied from an existing libm; re-running reproduces every digit.
"""
from mpmath import mp, mpf
import mpmath

mp.dps = 50


def round_bits(x, p):
    """x rounded to nearest with p significant bits (ties to even)."""
    x = mpf(x)
    if x == 0:
        return mpf(0)
    m, e = mpmath.frexp(x)  # x = m * 2^e, 0.5 <= |m| < 1
    n = mpmath.nint(mpmath.ldexp(m, p))
    return mpmath.ldexp(n, e - p)


def hexf(x, p):
    """C99 hex literal of x, which must have at most p significant bits."""
    x = mpf(x)
    assert round_bits(x, p) == x
    if x == 0:
        return "0.0" + ("f" if p == 24 else "")
    s = "-" if x < 0 else ""
    m, e = mpmath.frexp(abs(x))
    e -= 1
    m = m * 2  # [1, 2)
    if p == 53:
        frac = int(mpmath.ldexp(m - 1, 52))
        return "%s0x1.%013xp%+d" % (s, frac, e)
    frac = int(mpmath.ldexp(m - 1, 24))  # 23 bits padded to 24
    return "%s0x1.%06xp%+df" % (s, frac, e)


def split(x, head_bits, p):
    """x = head + tail, head with head_bits significant bits, tail in format p."""
    h = round_bits(x, head_bits)
    t = round_bits(x - h, p)
    return h, t


# ---------------------------------------------------------------- Remez --

def remez(f, basis, w, a, b, iters=12, grid=800):
    """Coefficients c minimising max_{a<=t<=b} |w(t) (f(t) - sum c_i basis_i(t))|."""
    a, b = mpf(a), mpf(b)
    n = len(basis)
    ref = sorted(a + (b - a) * (1 - mpmath.cos(mp.pi * (i + mpf(0.5)) / (n + 1))) / 2
                 for i in range(n + 1))
    ref = [t if t != 0 else (b - a) * mpf(2) ** -20 for t in ref]
    gridpts = [a + (b - a) * (1 - mpmath.cos(mp.pi * i / (grid - 1))) / 2 for i in range(grid)]
    gridpts = [g for g in gridpts if g != 0]
    best = None
    for _ in range(iters):
        A = mpmath.matrix(n + 1, n + 1)
        rhs = mpmath.matrix(n + 1, 1)
        for k, t in enumerate(ref):
            for i in range(n):
                A[k, i] = basis[i](t)
            A[k, n] = (-1) ** k / w(t)
            rhs[k] = f(t)
        sol = mpmath.lu_solve(A, rhs)
        c = [sol[i] for i in range(n)]

        def err(t):
            return w(t) * (f(t) - sum(c[i] * basis[i](t) for i in range(n)))

        ev = [err(t) for t in gridpts]
        # one extremum per run of constant sign
        ext = []
        i = 0
        while i < len(ev):
            j = i
            k = i
            while j < len(ev) and (ev[j] >= 0) == (ev[i] >= 0):
                if abs(ev[j]) > abs(ev[k]):
                    k = j
                j += 1
            # refine between neighbours by golden section on |err|
            lo = gridpts[max(k - 1, 0)]
            hi = gridpts[min(k + 1, len(gridpts) - 1)]
            g = (mpmath.sqrt(5) - 1) / 2
            for _ in range(24):
                m1 = hi - g * (hi - lo)
                m2 = lo + g * (hi - lo)
                if abs(err(m1)) > abs(err(m2)):
                    hi = m2
                else:
                    lo = m1
            tt = (lo + hi) / 2
            if abs(err(tt)) < abs(ev[k]):
                tt = gridpts[k]
            ext.append(tt)
            i = j
        while len(ext) > n + 1:
            if abs(err(ext[0])) < abs(err(ext[-1])):
                ext.pop(0)
            else:
                ext.pop()
        m = max(abs(e) for e in ev)
        done = best is not None and abs(m - best[1]) < m * mpf(2) ** -12
        best = (c, m)
        if len(ext) < n + 1 or done:
            break
        ref = ext
    return best


def check(f, basis, w, a, b, c, n=3000):
    a, b = mpf(a), mpf(b)
    m = mpf(0)
    for i in range(n):
        t = a + (b - a) * (1 - mpmath.cos(mp.pi * (i + mpf(0.5)) / n)) / 2
        if t == 0:
            continue
        e = abs(w(t) * (f(t) - sum(c[i2] * basis[i2](t) for i2 in range(len(c)))))
        m = max(m, e)
    return m


def fit(name, f, ncoef, w, a, b, p, out):
    basis = [(lambda k: (lambda t: t ** k))(k) for k in range(ncoef)]
    c, _ = remez(f, basis, w, a, b)
    cr = [round_bits(ci, p) for ci in c]
    e = check(f, basis, w, a, b, cr)
    out.append("/* %s: degree %d on [%s, %s], weighted error 2^%.1f */" % (
        name, ncoef - 1, mpmath.nstr(mpf(a), 6), mpmath.nstr(mpf(b), 6),
        float(mpmath.log(e, 2))))
    for i, ci in enumerate(cr):
        out.append("#define %s%d %s" % (name, i, hexf(ci, p)))


# ---------------------------------------------------------- functions --

def sin_s(z):  # sin(x) = x + x^3 S(x^2)
    x = mpmath.sqrt(z)
    return (mpmath.sin(x) - x) / (x * z)


def sin_w(z):
    x = mpmath.sqrt(z)
    return x * z / mpmath.sin(x)


def cos_c(z):  # cos(x) = 1 - x^2/2 + x^4 C(x^2)
    return (mpmath.cos(mpmath.sqrt(z)) - 1 + z / 2) / (z * z)


def cos_w(z):
    return z * z / mpmath.cos(mpmath.sqrt(z))


def exp_e(r):  # exp(r) = 1 + r + r^2 E(r)
    return (mpmath.exp(r) - 1 - r) / (r * r)


def exp_w(r):
    return r * r / mpmath.exp(r)


def log_p(r):  # log1p(r) = r - r^2/2 + r^3 P(r)
    return (mpmath.log1p(r) - r + r * r / 2) / (r ** 3)


def log_w(r):
    return r ** 3 / mpmath.log1p(r)


def atan_a(z):  # atan(u) = u + u^3 A(u^2)
    u = mpmath.sqrt(z)
    return (mpmath.atan(u) - u) / (u * z)


def atan_w(z):
    u = mpmath.sqrt(z)
    return u * z / mpmath.atan(u)


def main():
    out = []
    P = {53: "double", 24: "float"}
    pio4sq = (mp.pi / 4) ** 2 * (1 + mpf(2) ** -40)

    # --- constants -------------------------------------------------------
    out.append("/* ---- constants ---- */")
    h, t = split(mp.pi / 2, 53, 53)
    out.append("#define PIO2_HI %s\n#define PIO2_LO %s" % (hexf(h, 53), hexf(t, 53)))
    h, t = split(mp.pi, 53, 53)
    out.append("#define PI_HI %s\n#define PI_LO %s" % (hexf(h, 53), hexf(t, 53)))
    h, t = split(mp.pi / 4, 53, 53)
    out.append("#define PIO4_HI %s\n#define PIO4_LO %s" % (hexf(h, 53), hexf(t, 53)))
    h, t = split(3 * mp.pi / 4, 53, 53)
    out.append("#define PI3O4_HI %s\n#define PI3O4_LO %s" % (hexf(h, 53), hexf(t, 53)))
    h, t = split(mp.pi / 2, 24, 24)
    out.append("#define PIO2F_HI %s\n#define PIO2F_LO %s" % (hexf(h, 24), hexf(t, 24)))
    h, t = split(mp.pi, 24, 24)
    out.append("#define PIF_HI %s\n#define PIF_LO %s" % (hexf(h, 24), hexf(t, 24)))
    h, t = split(mp.pi / 4, 24, 24)
    out.append("#define PIO4F_HI %s\n#define PIO4F_LO %s" % (hexf(h, 24), hexf(t, 24)))
    h, t = split(3 * mp.pi / 4, 24, 24)
    out.append("#define PI3O4F_HI %s\n#define PI3O4F_LO %s" % (hexf(h, 24), hexf(t, 24)))

    # sin/cos medium range: n = round(x 2/pi) < 2^20 (float 2^10); pi/2 in
    # chunks with 33 (float 14) significant bits so that n * chunk is exact
    for nm, chunk, nchunks, p in (("PIO2_C", 33, 3, 53), ("PIO2F_C", 14, 4, 24)):
        rest = mp.pi / 2
        for i in range(nchunks):
            c = round_bits(rest, chunk)
            out.append("#define %s%d %s" % (nm, i + 1, hexf(c, p)))
            rest -= c
        out.append("#define %s%d %s" % (nm, nchunks + 1, hexf(round_bits(rest, p), p)))
    out.append("#define INV_PIO2 %s" % hexf(round_bits(2 / mp.pi, 53), 53))
    out.append("#define INV_PIO2F %s" % hexf(round_bits(2 / mp.pi, 24), 24))

    # exp: k = round(x * 64/ln2), |k| < 2^17 -> head of ln2/64 with 36 bits
    L = mp.log(2) / 64
    out.append("#define EXP_INVL %s /* 64/ln2 */" % hexf(round_bits(64 / mp.log(2), 53), 53))
    h = round_bits(L, 36)
    t = round_bits(L - h, 53)
    out.append("#define EXP_L1 %s /* ln2/64, 36-bit head */\n#define EXP_L2 %s" % (
        hexf(h, 53), hexf(t, 53)))
    # expf: k = round(x * 32/ln2), |k| < 2^13: two 11-bit heads and a tail
    L = mp.log(2) / 32
    out.append("#define EXPF_INVL %s /* 32/ln2 */" % hexf(round_bits(32 / mp.log(2), 24), 24))
    h1 = round_bits(L, 11)
    h2 = round_bits(L - h1, 11)
    t = round_bits(L - h1 - h2, 24)
    out.append("#define EXPF_L1 %s\n#define EXPF_L2 %s\n#define EXPF_L3 %s" % (
        hexf(h1, 24), hexf(h2, 24), hexf(t, 24)))
    # log: k * ln2, |k| < 2^11 -> 42-bit head; logf: |k| < 2^8 -> 16-bit head
    h = round_bits(mp.log(2), 42)
    t = round_bits(mp.log(2) - h, 53)
    out.append("#define LN2_HI %s\n#define LN2_LO %s" % (hexf(h, 53), hexf(t, 53)))
    h = round_bits(mp.log(2), 16)
    t = round_bits(mp.log(2) - h, 24)
    out.append("#define LN2F_HI %s\n#define LN2F_LO %s" % (hexf(h, 24), hexf(t, 24)))
    h, t = split(1 / mp.log(10), 53, 53)
    out.append("#define INVLN10_HI %s\n#define INVLN10_LO %s" % (hexf(h, 53), hexf(t, 53)))
    h, t = split(1 / mp.log(10), 24, 24)
    out.append("#define INVLN10F_HI %s\n#define INVLN10F_LO %s" % (hexf(h, 24), hexf(t, 24)))

    # --- polynomials -----------------------------------------------------
    out.append("/* ---- polynomials ---- */")
    tiny = mpf(2) ** -60
    fit("SIN_S", sin_s, 7, sin_w, tiny, pio4sq, 53, out)
    fit("COS_C", cos_c, 6, cos_w, tiny, pio4sq, 53, out)
    fit("SINF_S", sin_s, 5, sin_w, tiny, pio4sq, 24, out)
    fit("COSF_C", cos_c, 4, cos_w, tiny, pio4sq, 24, out)
    re = mp.log(2) / 128 * (1 + mpf(2) ** -8)
    fit("EXP_E", exp_e, 5, exp_w, -re, re, 53, out)
    re = mp.log(2) / 64 * (1 + mpf(2) ** -8)
    fit("EXPF_E", exp_e, 3, exp_w, -re, re, 24, out)
    fit("LOG_P", log_p, 8, log_w, -mpf(2) ** -7, mpf(2) ** -7, 53, out)
    fit("LOGF_P", log_p, 5, log_w, -mpf(2) ** -5, mpf(2) ** -5, 24, out)
    az = (mpf(1) / 32 * (1 + mpf(2) ** -8)) ** 2
    fit("ATAN_A", atan_a, 6, atan_w, tiny, az, 53, out)
    fit("ATANF_A", atan_a, 3, atan_w, tiny, az, 24, out)

    # --- tables ----------------------------------------------------------
    def table2(name, ctype, vals, p, per_line=2):
        out.append("static const %s %s[%d] = {" % (ctype, name, len(vals)))
        items = [hexf(v, p) for v in vals]
        for i in range(0, len(items), per_line):
            out.append("    " + ", ".join(items[i:i + per_line]) + ",")
        out.append("};")

    for N, p, nm, ct in ((64, 53, "exp_tab", "double"), (32, 24, "expf_tab", "float")):
        vals = []
        for j in range(N):
            v = mpf(2) ** (mpf(j) / N)
            h = round_bits(v, p)
            vals += [h, round_bits(v - h, p)]
        out.append("/* 2^(j/%d) as head, tail */" % N)
        table2(nm, ct, vals, p)

    # log: index j = top bits of the mantissa m in [1,2); c_j ~ 1/midpoint with
    # cbits significant bits (so c*m - 1 is exact); j=0 uses c=1, the last j
    # uses c=1/2. For j >= jadj the caller uses k+1 and the table holds
    # log(1/c_j) - ln2, so that the result near x = 1 comes from the last
    # interval without cancellation.
    for N, cbits, p, nm, ct, jadj in ((128, 8, 53, "log_tab", "double", 53),
                                      (32, 6, 24, "logf_tab", "float", 13)):
        vals = []
        worst = mpf(0)
        for j in range(N):
            if j == 0:
                c = mpf(1)
            elif j == N - 1:
                c = mpf(1) / 2
            else:
                mid = 1 + (j + mpf(0.5)) / N
                c = round_bits(1 / mid, cbits)
            lo_m, hi_m = 1 + mpf(j) / N, 1 + mpf(j + 1) / N
            worst = max(worst, abs(lo_m * c - 1), abs(hi_m * c - 1))
            Lv = -mp.log(c)
            if j >= jadj:
                Lv -= mp.log(2)
            h = round_bits(Lv, p)
            vals += [c, h, round_bits(Lv - h, p)]
        out.append("/* c_j, log(1/c_j) head, tail (j >= %d: minus ln2); max |m c - 1| = 2^%.3f */" % (
            jadj, float(mpmath.log(worst, 2))))
        table2(nm, ct, vals, p, 3)

    for p, nm, ct in ((53, "atan_tab", "double"), (24, "atanf_tab", "float")):
        vals = []
        for j in range(17):
            v = mp.atan(mpf(j) / 16)
            h = round_bits(v, p)
            vals += [h, round_bits(v - h, p)]
        out.append("/* atan(j/16) as head, tail */")
        table2(nm, ct, vals, p)

    # 2/pi: bit i (i >= 1) is the coefficient of 2^-i; word w holds bits
    # 32w+1 .. 32w+32, most significant first.
    words = []
    with mp.workprec(1600):  # 40 words need 1280 exact bits
        v = 2 / mp.pi
        for w in range(40):
            v *= 2 ** 32
            d = int(mpmath.floor(v))
            words.append(d)
            v -= d
    out.append("/* bits of 2/pi, 32 per word, most significant first */")
    out.append("static const uint32_t two_over_pi[%d] = {" % len(words))
    for i in range(0, len(words), 6):
        out.append("    " + ", ".join("0x%08xu" % x for x in words[i:i + 6]) + ",")
    out.append("};")
    print("\n".join(out))


if __name__ == "__main__":
    main()
