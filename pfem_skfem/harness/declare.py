"""A script's own options, declared as a table: one row an option (its validator, default and
help), in the one spelling of :data:`.options.OPTION_SPELLING`; the options several scripts
share are declared through their groups of :mod:`.options` instead.
"""
import argparse

from .options import opt, option_name


def own_options(parser, **options):
    """Add a script's own options to ``parser`` (or an argument group), in the order given.

    Each keyword is an option's name, its dest (``mu_f``: ``--mu-f``, ``args.mu_f``;
    :func:`.options.option_name`), and its row: ``(validator, default, help)``, or an
    :class:`.options.opt` (``type=`` the validator) where it also needs ``nargs``, ``dest`` or
    ``metavar``. The validator is an argparse type of :mod:`.options` (``positive_float``,
    ``in_range(...)``), a list or tuple of choices, or ``bool`` for a switch: default False,
    ``--name`` sets it; default True, ``--name`` / ``--no-name``. Returns ``parser``::

        own_options(p, mu_f=(nonnegative_float, 5.0, "friction coefficient of the floor"),
                    studies=(bool, True, "the mesh and step twins"),
                    k=opt([0.04, 0.02], "yield numbers", type=yield_number, nargs="+"))
    """
    for name, row in options.items():
        o = row if isinstance(row, opt) else opt(row[1], row[2], type=row[0])
        kwargs = dict(default=o.default, help=(o.help or "") + (f"; {o.why}" if o.why else ""))
        if o.type is bool:
            kwargs["action"] = argparse.BooleanOptionalAction if o.default else "store_true"
        elif isinstance(o.type, (list, tuple)):
            kwargs["choices"] = o.type
        else:
            kwargs["type"] = o.type
        kwargs.update({k: getattr(o, k) for k in ("nargs", "dest", "metavar")
                       if getattr(o, k) is not None})
        parser.add_argument(option_name(name), **kwargs)
    return parser


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
