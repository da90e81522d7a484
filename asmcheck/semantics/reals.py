"""Reals as ASMETA's simulator computes them: Java ``double`` arithmetic (division by zero is an
infinity or NaN, ``Math.pow`` never fails), and Java's narrowing of a double to ``long`` or ``int``
(``rtoi`` of NaN is 0, of an infinity the largest value), as the standard-library functions of the
simulator (StandardLibrary.java) apply them."""
from __future__ import annotations

import math


def java_div(a, b):
    """``div`` is a division of doubles (Java's ``/``): by zero it gives an infinity or NaN."""
    if a is None or b is None:
        return None
    x, y = float(a), float(b)
    if y == 0:
        if x == 0 or x != x:
            return math.nan
        return math.copysign(math.inf, x) * math.copysign(1.0, y)
    return x / y


JAVA_LONG_MIN, JAVA_LONG_MAX = -(1 << 63), (1 << 63) - 1
JAVA_INT_MIN, JAVA_INT_MAX = -(1 << 31), (1 << 31) - 1


def java_to_integral(x, lo=JAVA_LONG_MIN, hi=JAVA_LONG_MAX) -> int:
    """Java's narrowing of a double to long (or int): towards zero, NaN is 0, out of range saturates."""
    if type(x) is int:
        return x
    if x != x:
        return 0
    if x >= hi:
        return hi
    if x <= lo:
        return lo
    return int(x)


def java_compare(a, b) -> int:
    """``Double.compareTo``: NaN above everything (and equal to itself), -0.0 below 0.0."""
    def key(v):
        v = float(v)
        if v != v:
            return (2, 0.0)
        return (1, v, math.copysign(1.0, v))
    ka, kb = key(a), key(b)
    return (ka > kb) - (ka < kb)


def java_pow(a, b) -> float:
    """``Math.pow``: never fails; overflow is an infinity, a domain error NaN."""
    x, y = float(a), float(b)
    if y != y:
        return math.nan
    if y == 0:
        return 1.0
    if abs(x) == 1 and math.isinf(y):
        return math.nan
    try:
        return math.pow(x, y)
    except OverflowError:
        odd = y.is_integer() and abs(y) < 2 ** 53 and int(y) % 2 == 1
        return -math.inf if x < 0 and odd else math.inf
    except ValueError:
        return math.nan


def java_rtoi(x):
    if x is None:
        return None
    return java_to_integral(x)


def java_round(x):
    """``Math.round``: floor(x + 0.5) as a long (NaN is 0, saturating)."""
    if x is None:
        return None
    if type(x) is int:
        return x
    if x != x or math.isinf(x):
        return java_to_integral(x)
    return java_to_integral(math.floor(x + 0.5))


def java_floor(x):
    """ASMETA's floor of a Real narrows ``Math.floor`` to a Java int (32 bits, saturating)."""
    if x is None:
        return None
    if type(x) is int:
        return x
    if x != x or math.isinf(x):
        return java_to_integral(x, JAVA_INT_MIN, JAVA_INT_MAX)
    return java_to_integral(float(math.floor(x)), JAVA_INT_MIN, JAVA_INT_MAX)


def java_abs(x):
    """ASMETA's abs of a Real is ``d > 0 ? d : -d`` (so abs(0.0) is -0.0, and NaN stays NaN)."""
    if x is None:
        return None
    if type(x) is float:
        return x if x > 0 else -x
    return abs(x)


def java_max(a, b):
    if a is None or b is None:
        return None
    if type(a) is float or type(b) is float:
        return a if java_compare(a, b) > 0 else b
    return max(a, b)


def java_min(a, b):
    if a is None or b is None:
        return None
    if type(a) is float or type(b) is float:
        return a if java_compare(a, b) < 0 else b
    return min(a, b)


def java_pwr(a, b):
    if a is None or b is None:
        return None
    return java_pow(a, b)


def java_sqrt(a):
    """``Math.sqrt``: NaN below zero."""
    if a is None:
        return None
    a = float(a)
    if a != a or a < 0:
        return math.nan
    return math.sqrt(a)
