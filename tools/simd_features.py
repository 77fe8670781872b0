"""Print the widest SIMD features NumPy dispatches to on this CPU, for ``NPY_DISABLE_CPU_FEATURES``.

``make test-simd`` runs the fast tests once with these features disabled, so NumPy takes its
narrower code paths (other rounding in ``exp``, ``sin``, reductions …) as it would on an older
CPU: a test that pins the last digits of one CPU fails here instead of on someone else's machine.
Prints nothing when the CPU has no dispatch target above NumPy's baseline.
"""

from __future__ import annotations


def widest_features() -> list:
    """The dispatch targets above the baseline that this CPU supports, widest first."""
    try:
        from numpy._core._multiarray_umath import __cpu_dispatch__, __cpu_features__
    except ImportError:  # NumPy 1.x
        from numpy.core._multiarray_umath import __cpu_dispatch__, __cpu_features__
    return [f for f in reversed(__cpu_dispatch__) if __cpu_features__.get(f)]


if __name__ == "__main__":
    print(" ".join(widest_features()))
