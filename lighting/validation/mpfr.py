r"""The part of mpmath's context that the 80-digit model references use, on MPFR through gmpy2.

The general path of the stability sweep (:mod:`lighting.validation.general`) evaluates a model's whole ``f_r``
at every case and at twice as many perturbed inputs as the case has inputs and shape parameters.  Every
mpmath operation goes through Python (the number's wrapper, then a tuple normalized by gmpy2's helper); MPFR
does the same correctly rounded operation in C, several times faster.  :class:`MPFRContext` gives the
references (:mod:`lighting.validation.model_references`, written against mpmath's names) MPFR numbers at the
same precision in bits, so the formulas keep one home and run on either arithmetic.

The two differ where MPFR's exponent range ends (binary exponents of about ±2^30 in gmpy2's contexts; mpmath's
have no bound): a value that underflows or overflows it, or a division by zero, sets the context's flags
(:meth:`MPFRContext.exceptional`), and the caller computes that model at that input again in mpmath.
Elsewhere both round each basic operation correctly at the same precision and their elementary functions agree
to the last few of its 269 bits: the double-double values and condition numbers the sweep keeps are the same
(``tests/validation/test_mpfr.py``; the default run's report files, byte for byte).
"""

from __future__ import annotations

from contextlib import contextmanager

__all__ = ["MPFRContext", "mpfr_context"]


class MPFRContext:
    """mpmath's ``mp`` as the references use it (``mpf``, ``sqrt``, ``pi``, ``workdps`` …), on gmpy2's MPFR.

    ``workdps`` and ``workprec`` enter a gmpy2 context of that precision with its flags cleared; :meth:`exceptional`
    says whether anything computed since underflowed, overflowed or divided by 0.
    """

    def __init__(self, gmpy2):
        self._gmpy2 = gmpy2
        self.mpf = gmpy2.mpfr
        self.mpc = gmpy2.mpc
        for name in ("sqrt", "exp", "log", "sin", "cos", "tan", "atan", "atan2", "erf", "erfc", "fsum"):
            setattr(self, name, getattr(gmpy2, name))
        self.zero = gmpy2.mpfr(0)
        self.one = gmpy2.mpfr(1)
        self._pi: dict = {}
        self._prec = None  # the innermost precision entered through workprec / workdps (None: none entered)

    @property
    def prec(self) -> int:
        # The references read it for every constant they use (model_references._c, pi): kept here, it is an
        # attribute read instead of a query of gmpy2's thread-local context.
        if self._prec is not None:
            return self._prec
        return self._gmpy2.get_context().precision

    @property
    def pi(self):
        """π rounded to the working precision."""
        prec = self.prec
        value = self._pi.get(prec)
        if value is None:
            value = self._pi[prec] = self._gmpy2.const_pi()
        return value

    @staticmethod
    def power(x, y):
        return x**y

    @contextmanager
    def workprec(self, bits: int):
        g = self._gmpy2
        ctx = g.get_context().copy()
        ctx.precision = int(bits)
        ctx.clear_flags()
        before = self._prec
        with g.context(ctx) as active:
            self._prec = int(bits)
            try:
                yield active
            finally:
                self._prec = before

    def workdps(self, dps: int):
        from mpmath.libmp import dps_to_prec  # the bits mpmath's workdps would work at

        return self.workprec(dps_to_prec(dps))

    def clear_flags(self) -> None:
        """Clear the working context's flags (what :meth:`exceptional` reads)."""
        self._gmpy2.get_context().clear_flags()

    def exceptional(self) -> bool:
        """Whether the working context's flags show an underflow, overflow, division by 0 or invalid operation."""
        c = self._gmpy2.get_context()
        return bool(c.underflow or c.overflow or c.divzero or c.invalid or c.erange)


def mpfr_context() -> MPFRContext | None:
    """The :class:`MPFRContext`, or None where gmpy2 is not installed (the references then run in mpmath).

    Examples
    --------
    >>> ctx = mpfr_context()
    >>> with ctx.workdps(80):
    ...     root = ctx.sqrt(ctx.mpf(2))
    ...     print(ctx.prec, float(root) == 2**0.5, ctx.exceptional())
    269 True False
    """
    try:
        import gmpy2
    except ImportError:
        return None
    return MPFRContext(gmpy2)
