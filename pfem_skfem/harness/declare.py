"""A script's options as a table of keywords, and its cases' keywords read back from them.

:func:`own_options` declares the options of a script that belong to no group of
:mod:`.options` (a footing's width ``--B``, a study's ``--mc-width``) as the groups do:
one keyword each, its default or an :class:`~.options.opt`, the name spelt with hyphens
(:func:`~.options.option_name`). :func:`option_values` gives back the values of the
options named, as the keywords of a case (``run_case(a, **option_values(args, "nr",
"steps"))``); :func:`keywords_of`, those of a case's function that are options;
:func:`checkpoint_keywords`, the checkpoints asked for.
"""
import argparse

from .options import opt, option_name, positive_float


def own_options(parser, type=positive_float, **options):
    """Add a script's own options: each keyword an option (``mc_width`` -> ``--mc-width``,
    ``args.mc_width``), its value an :class:`~.options.opt` (default, help, and where it
    differs the validator ``type``, ``nargs``, ``dest``, ``metavar``) or a row
    ``(validator, default, help)``; ``type`` is the validator of the others (default
    :func:`~.options.positive_float`). A validator may be a list or tuple of choices, or
    ``bool`` for a switch (default False: ``--name`` sets it; True: ``--name`` /
    ``--no-name``). Returns ``parser``.

    ``own_options(g, B=opt(1.0, "footing width"), uniform=opt(2, "...", type=nonnegative_int))``
    """
    for name, o in options.items():
        if isinstance(o, tuple) and len(o) == 3:
            o = opt(o[1], o[2], type=o[0])
        if not isinstance(o, opt):
            raise TypeError(f"own_options: {name} needs an opt(default, help), got {o!r}")
        validator = o.type or type
        kwargs = dict(default=o.default, help=(o.help or "") + (f"; {o.why}" if o.why else ""))
        if validator is bool:
            kwargs["action"] = argparse.BooleanOptionalAction if o.default else "store_true"
        elif isinstance(validator, (list, tuple)):
            kwargs["choices"] = validator
        else:
            kwargs["type"] = validator
        kwargs.update({key: getattr(o, key) for key in ("nargs", "dest", "metavar")
                       if getattr(o, key) is not None})
        parser.add_argument(option_name(name), **kwargs)
    return parser


def option_values(args, *names, **renamed):
    """{name: ``args.name``} for each of ``names``, and {keyword: ``args.option``} for each
    ``keyword=option`` of ``renamed``: a case's keywords read from the parsed options, in
    that order."""
    return {**{name: getattr(args, name) for name in names},
            **{key: getattr(args, name) for key, name in renamed.items()}}


def checkpoint_keywords(args):
    """``--checkpoint-dir`` and ``--checkpoint-every`` (:func:`~.options.checkpoint_options`)
    as a case's keywords, none without a directory: the keywords name a case's kept result
    (``--results-dir``), so that a run without checkpoints finds the results kept before
    (as :func:`~.options.solver_keyword` leaves out the default solver)."""
    if getattr(args, "checkpoint_dir", None) is None:
        return {}
    return {"checkpoint_dir": args.checkpoint_dir, "checkpoint_every": args.checkpoint_every}


def keywords_of(function, args, **given):
    """The keywords of ``function`` that are options of ``args`` (a parsed namespace, one
    dest a keyword: the options are named after the quantities), with ``given`` beside
    (replacing or adding): the keywords of a case of a study from its command line.

    ``run_case(**keywords_of(run_case, args, label="base"))``
    """
    import inspect

    names = [n for n, p in inspect.signature(function).parameters.items()
             if p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY) and hasattr(args, n)]
    return {n: getattr(args, n) for n in names} | given
