"""The harness is a leaf (issue 37): it imports nothing of the science, and the old
module ``pfem_skfem.report`` still offers what it offered (one release)."""
import ast
from pathlib import Path

import pfem_skfem

PACKAGE = Path(pfem_skfem.__file__).resolve().parent
HARNESS = PACKAGE / "harness"


def _imports(path):
    """The modules ``path`` imports (relative imports made absolute), at any depth."""
    tree = ast.parse(path.read_text())
    package = ["pfem_skfem", *path.relative_to(PACKAGE).parent.parts]
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[:len(package) - node.level + 1]
                found.append(".".join(base + ([node.module] if node.module else [])))
            else:
                found.append(node.module)
    return found


def test_the_harness_imports_no_science_module():
    files = sorted(HARNESS.glob("*.py"))
    assert {f.stem for f in files} >= {"report", "options", "progress", "sweeps", "store",
                                       "figures"}
    for path in files:
        for name in _imports(path):
            if name == "pfem_skfem" or name.startswith("pfem_skfem."):
                assert name == "pfem_skfem.harness" or name.startswith("pfem_skfem.harness."), \
                    f"{path.name} imports {name}"


def test_no_module_of_the_package_imports_through_the_report_shim():
    for path in PACKAGE.rglob("*.py"):
        if path.name == "report.py" and path.parent == PACKAGE:
            continue
        assert "pfem_skfem.report" not in _imports(path), path


def test_the_old_report_module_offers_what_it_offered():
    from pfem_skfem import report
    old = """Quantity Report relative_error HARNESS_OPTIONS thinned run_script script_main
        ScriptParser base_parser OUTPUT_PATHS output_path_problem OptionError in_range
        positive_float nonnegative_float positive_int nonnegative_int workers friction_angle
        positive_angle poisson_ratio fraction theta_weight element_count positive
        scheduler_address sweep_options volume_correction_option checkpoint_options
        alpha_advected_option progress progress_bar DamagedFileError checkpoint_path
        save_run load_run sitting SweepError run_cases result_path pyplot figure_dir
        save_figure figure_problems inspect_figures FIGURE_PIXELS SMALLEST_FONT""".split()
    assert [n for n in old if not hasattr(report, n)] == []


def test_quick_sizes_leave_every_option_the_user_gave():
    """--quick sets the options the user did not give, and none that were given, even at
    their default value (a --steps 300 at the default 300 once became the quick 100 and
    silently tripled the time step of a run asked for by hand)."""
    from pfem_skfem.harness.options import base_parser, positive_int
    parser = base_parser("x", quick=dict(steps=100, n=4))
    parser.add_argument("--steps", type=positive_int, default=300)
    parser.add_argument("--n", type=positive_int, default=16)
    args = parser.parse_args(["--quick"])
    assert (args.steps, args.n) == (100, 4)
    args = parser.parse_args(["--quick", "--steps", "300"])
    assert (args.steps, args.n) == (300, 4)
    args = parser.parse_args(["--quick", "--n=16", "--steps", "7"])
    assert (args.steps, args.n) == (7, 16)
    args = parser.parse_args(["--steps", "300"])
    assert (args.steps, args.n) == (300, 16)
