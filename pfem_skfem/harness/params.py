"""A benchmark run's parameters as one frozen dataclass that builds both its scene and its
checkpoint keys (issue 52, item 4).

A script that wrote its keys by hand beside the scene's construction could add a parameter
to the scene and forget it in the keys, and a resumed run would then go on from another
scene's state. With the parameters one object, its ``scene()`` and its ``keys()`` read the
same fields: :func:`keys_of` gives the keys of such an object, every field by name, less
those the keys never held (a solver, which changes no state a checkpoint holds), with
values replaced or added where the keys hold another form (a material object's repr).
"""
from dataclasses import fields

__all__ = ["keys_of"]


def keys_of(params, omit=(), **given):
    """The checkpoint keys of ``params`` (a dataclass instance): {name: value} of each field
    not named in ``omit``, then ``given`` beside (replacing or adding), a dict for
    :func:`~pfem_skfem.harness.store.checkpoint_path`. A name in ``omit`` that is no field
    raises ValueError (a renamed field would otherwise silently enter the keys)."""
    names = [f.name for f in fields(params)]
    if unknown := set(omit) - set(names):
        raise ValueError(f"omit names no field of {type(params).__name__}: {sorted(unknown)}")
    return {n: getattr(params, n) for n in names if n not in omit} | given
