"""A script's options as a table of keywords, and its cases' keywords read back from them.

:func:`own_options` declares the options of a script that belong to no group of
:mod:`.options` (a footing's width ``--B``, a study's ``--mc-width``) as the groups do:
one keyword each, its default or an :class:`~.options.opt`, the name spelt with hyphens
(:func:`~.options.option_name`). :func:`option_values` gives back the values of the
options named, as the keywords of a case (``run_case(a, **option_values(args, "nr",
"steps"))``).
"""
from .options import opt, option_name, positive_float


def own_options(parser, type=positive_float, **options):
    """Add a script's own options: each keyword an option (``mc_width`` -> ``--mc-width``,
    ``args.mc_width``), its value an :class:`~.options.opt` (default, help, and where it
    differs the validator ``type``, ``nargs``, ``dest``, ``metavar``); ``type`` is the
    validator of the others (default :func:`~.options.positive_float`). Returns ``parser``.

    ``own_options(g, B=opt(1.0, "footing width"), uniform=opt(2, "...", type=nonnegative_int))``
    """
    for name, o in options.items():
        if not isinstance(o, opt):
            raise TypeError(f"own_options: {name} needs an opt(default, help), got {o!r}")
        kwargs = dict(type=o.type or type, default=o.default,
                      help=(o.help or "") + (f"; {o.why}" if o.why else ""))
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
