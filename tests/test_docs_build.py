"""The documentation site builds with warnings as errors (what `make docs` runs), and the pages that
are generated rather than written hold what they should: the API reference of the compiled and
the Python classes, and the benchmark headline included from bench/README.md."""
import html
import importlib.util
import os
import re
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    if importlib.util.find_spec("mkdocs") is None:
        pytest.skip("mkdocs is not installed: pip install 'hovi[docs]' (mkdocs-material, mkdocstrings-python), "
                    "or make setup (requirements-dev.txt)")
    out = tmp_path_factory.mktemp("site")
    env = dict(os.environ, NO_MKDOCS_2_WARNING="1")
    done = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--config-file",
                           os.path.join(ROOT, "mkdocs.yml"), "--site-dir", str(out)],
                          cwd=ROOT, env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, f"mkdocs build --strict failed ({done.returncode}):\n{done.stdout}\n{done.stderr}"
    return out


def test_the_examples_page_lists_the_registry():
    """docs/reference/examples.md's table is the registry's (hovi.examples.REGISTRY), row for row."""
    import hovi.examples
    with open(os.path.join(ROOT, "docs", "reference", "examples.md")) as f:
        page = f.read()
    table = page.split("<!-- registry:begin -->")[1].split("<!-- registry:end -->")[0]
    rows = [r for r in table.strip().splitlines()[2:]]
    expected = [f"| `{e.kind}` | `{e.name}` | {e.description} | `hovi.examples.{e.target.replace(':', '.')}` |"
                for e in hovi.examples.REGISTRY]
    assert rows == expected, "docs/reference/examples.md's table differs from hovi.examples.REGISTRY"
    for e in hovi.examples.REGISTRY:  # every entry builds from its target
        assert callable(e.function), e


def _text(site, page):
    """The visible text of a built page's article, tags removed."""
    page_html = (site / page / "index.html").read_text(encoding="utf-8")
    article = page_html[page_html.index("<article"):page_html.index("</article>")]
    return re.sub(r"\s+", " ", html.unescape(re.sub(r"<[^>]+>", " ", article)))


def _anchors(site, page):
    return set(re.findall(r'id="(hovi\.[\w.]+)"', (site / page / "index.html").read_text(encoding="utf-8")))


def test_build_strict(site):
    """`mkdocs build --strict` exits 0 (in the fixture, which shows the output if not) with every page."""
    for page in ["index.html", "getting-started/index.html", "benchmarks/index.html", "reference/hovi/index.html"] + [
            f"tutorials/{t}/index.html" for t in ("simulate", "linearise", "constrain", "optimise", "view", "many")]:
        assert (site / page).is_file(), page


def test_api_reference_renders_compiled_and_python_members(site):
    anchors = _anchors(site, "reference/hovi")
    for name in ["hovi.Model", "hovi.Model.from_urdf", "hovi.Model.add_body", "hovi.Model.add_loop_constraint",
                 "hovi.Model.mass_matrix", "hovi.Model.n", "hovi.Integrator", "hovi.Integrator.rollout",
                 "hovi.Integrator.step", "hovi.Integrator.s", "hovi.Trajectory", "hovi.Trajectory.q",
                 "hovi.Trajectory.energy", "hovi.Linearizer", "hovi.Linearizer.step_jacobians",
                 "hovi.load_trajectory", "hovi.ModelError", "hovi.URDFError", "hovi.Integrator.rollout_batch",
                 "hovi.Integrator.step_batch", "hovi.TrajectoryBatch", "hovi.TrajectoryBatch.trajectory",
                 "hovi.StepBatch", "hovi.JacobianBatch", "hovi.Linearizer.rollout_jacobians_batch"]:
        assert name in anchors, f"{name} is missing from the API reference"
    text = _text(site, "reference/hovi")
    # docstrings of the compiled module (read by inspection) and of the Python layer
    assert "Load a URDF file (source: a path) or XML string" in text           # Model.from_urdf (C++)
    assert "Galerkin variational integrator of order 2s" in text     # Integrator (Python)
    assert "Number of Lobatto intervals" in text                     # Integrator.s, a property(doc=...)
    # a compiled method's signature comes from its pybind11 signature line, the line itself is gone
    assert re.search(r"add_spring\s*\(\s*joint\s*:\s*int\s*\|\s*str\s*,\s*stiffness\s*:\s*typing\s*\.\s*SupportsFloat", text), \
        "Model.add_spring's parameters are not rendered"
    assert "add_spring(self: hovi._core.Model" not in text
    models = _anchors(site, "reference/examples")
    assert {"hovi.examples.models.pendulum", "hovi.examples.models.acrobot", "hovi.examples.models.cartpole", "hovi.examples.models.fourbar",
            "hovi.examples.models.slider_crank"} <= models
    viewer = _anchors(site, "reference/viewer")
    assert {"hovi.vis.viewer.Viewer", "hovi.vis.viewer.Viewer.play", "hovi.vis.viewer.animation_html", "hovi.vis.video.render_video",
            "hovi.vis.geometry.model_shapes"} <= viewer
    assert {"hovi.distributed.rollout_batch", "hovi.distributed.step_batch", "hovi.distributed.one_step_batch",
            "hovi.distributed.solve_trajopt"} <= _anchors(site, "reference/distributed")
    trajopt = _anchors(site, "reference/trajopt")
    assert {"hovi.trajopt.Problem", "hovi.trajopt.solve", "hovi.trajopt.Result", "hovi.trajopt.ControlEffort",
            "hovi.trajopt.BodyPoint", "hovi.trajopt.Problem.add_cost"} <= trajopt


def test_benchmark_page_includes_the_headline(site):
    """The headline section of bench/README.md appears on the page, whole and as it is there."""
    readme = open(os.path.join(ROOT, "bench", "README.md"), encoding="utf-8").read()
    section = readme[readme.index("[start:headline]"):readme.index("[end:headline]")]
    rows = [line for line in section.splitlines() if line.startswith("| ") and not line.startswith("| comparison")]
    assert len(rows) > 10
    text = _text(site, "benchmarks")
    assert "Headline results" in text
    for row in (rows[0], rows[-1]):   # the first and the last row of the table, cell by cell
        for cell in (c.strip().replace("**", "").replace("`", "") for c in row.strip("|").split("|")):
            assert cell in text, f"benchmark page lacks {cell!r}"
    assert "What they show." in text and "--8<--" not in text
