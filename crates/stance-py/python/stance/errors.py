"""The exceptions of stance.

Bad input raises :class:`InputError` (also a :class:`ValueError`) with the Rust message naming
what to fix. Negative outcomes (an unstable CoM, an infeasible retiming, an empty polygon) are
values, not exceptions.
"""


class StanceError(Exception):
    """Root of every exception raised by stance."""


class InputError(StanceError, ValueError):
    """Bad input: a wrong shape, a non-finite number, an invalid contact or file."""


class UncertifiedError(StanceError, ArithmeticError):
    """A cone conversion floating point cannot decide or certify.

    Its certificate failed (also in exact arithmetic), or the cone's dimension is undecided (a
    direction within the rank tolerance but far above rounding, as a wrench cone written about a
    point 100 km away). The engine refuses to return an answer it cannot prove; retry with
    ``exact=True``, the wrench preconditioning for wrench cones, or check the input for structure
    degenerate at the scale of the tolerances.
    """


class NotInstalledError(StanceError, ImportError):
    """An optional resource is missing (JVRC-1's URDF: ``pip install jvrc-description``)."""


__all__ = ["StanceError", "InputError", "UncertifiedError", "NotInstalledError"]
