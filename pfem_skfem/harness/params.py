"""A run's parameters as one frozen dataclass, which builds its scene and names its
checkpoint (issue 52, item 4; the model: :class:`pfem_skfem.scene.columns.Column`).

A script that built its checkpoint's keys by hand (``keys = dict(a=a, nx=nx, ...)`` beside
the scene's construction) could add a parameter to the scene and forget it in the keys: a
resume would then go on from another scene's state. Its run's parameters, one dataclass,
build both: its own ``scene()`` method and its keys, every field (:func:`keys_of`) but
those declared ``metadata=UNKEYED`` or named in ``omit`` (a solver, which changes no state
a checkpoint holds; an end time a resumed run may change), so that a field added is a key
at once. :class:`Parameters` gives such a dataclass :meth:`~Parameters.keys` and
:meth:`~Parameters.of` (its fields from a script's options).
"""
from dataclasses import fields

__all__ = ["UNKEYED", "Parameters", "keys_of"]

#: a run's parameter that is no key of its checkpoint: one that does not change the run's
#: states (the solver) or that a resumed run may change (the end time), declared
#: ``field(default=..., metadata=UNKEYED)``
UNKEYED = {"keyed": False}


def keys_of(params, omit=(), **beside):
    """The checkpoint keys (:func:`~.store.checkpoint_path`) of a run whose parameters are
    the dataclass ``params``: {name: value} of its fields but those declared with
    ``metadata=UNKEYED`` and those named in ``omit``, then ``beside`` (added, or replacing).
    A name in ``omit`` that is no field raises ValueError (a renamed field would otherwise
    silently enter the keys)."""
    names = [f.name for f in fields(params)]
    if unknown := set(omit) - set(names):
        raise ValueError(f"omit names no field of {type(params).__name__}: {sorted(unknown)}")
    return {f.name: getattr(params, f.name) for f in fields(params)
            if f.metadata.get("keyed", True) and f.name not in omit} | beside


class Parameters:
    """The base of a run's parameters (a frozen dataclass whose ``scene()`` builds its
    scene): :meth:`keys`, its checkpoint's keys, and :meth:`of`, its parameters from the
    options of a script's command line."""

    def keys(self):
        """The checkpoint's keys: :func:`keys_of` these parameters."""
        return keys_of(self)

    @classmethod
    def of(cls, args, **given):
        """The parameters of the options of ``args`` (a parsed namespace) named as the
        fields (:func:`~.declare.keywords_of`), with ``given`` beside (replacing or adding)."""
        from .declare import keywords_of
        return cls(**keywords_of(cls, args, **given))
