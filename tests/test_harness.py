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
