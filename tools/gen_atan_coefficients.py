#!/usr/bin/env python3
"""Coefficients of core/math.h's atan2Upper: atan(x) = x + x z P(z), z = x^2, on
|x| <= tan(pi/8) (the range the pi/4 reduction leaves), P interpolating
(atan(sqrt z) / sqrt z - 1) / z at Chebyshev nodes, in exact rational arithmetic from the
alternating series, so no double rounding enters the fit. Prints the coefficients (constant
term first) and the worst relative error of the double evaluation against math.atan.

    python3 tools/gen_atan_coefficients.py [DEGREE+1 = 10]

Python standard library only.
"""
import math
import sys
from fractions import Fraction


def series(z, terms=60):
    """(atan(sqrt z) / sqrt z - 1) / z = sum_{k >= 1} (-1)^k z^(k-1) / (2k + 1), exactly."""
    total, power = Fraction(0), Fraction(1)
    for k in range(1, terms):
        total += (-1) ** k * power / (2 * k + 1)
        power *= z
    return total


def fit(n):
    t8 = math.tan(math.pi / 8)
    z_max = Fraction(t8 * t8) * Fraction(1000001, 1000000)
    nodes = [(z_max / 2) * (1 + Fraction(math.cos(math.pi * (j + 0.5) / n))) for j in range(n)]
    coef = [series(z) for z in nodes]
    for j in range(1, n):  # Newton divided differences
        for i in range(n - 1, j - 1, -1):
            coef[i] = (coef[i] - coef[i - 1]) / (nodes[i] - nodes[i - j])
    poly = [Fraction(0)] * n  # Newton form to monomials
    for i in range(n - 1, -1, -1):
        shifted = [Fraction(0)] + poly[:-1]
        poly = [shifted[k] - poly[k] * nodes[i] for k in range(n)]
        poly[0] += coef[i]
    return [float(c) for c in poly], t8


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 10
    coefficients, t8 = fit(n)
    worst = 0.0
    for i in range(1, 100001):
        x = t8 * i / 100000
        z, acc = x * x, 0.0
        for c in reversed(coefficients):
            acc = acc * z + c
        worst = max(worst, abs(x + x * z * acc - math.atan(x)) / math.atan(x))
    for c in coefficients:
        print("%.17g," % c)
    print("worst relative error %.3g" % worst, file=sys.stderr)


if __name__ == "__main__":
    main()
