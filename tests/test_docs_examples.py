"""Every ```python block of README.md and docs/**/*.md runs, as written.

A page's blocks run in order in one namespace (fresh per page), in an empty temporary working
directory outside the repository, where files the examples write (``run.npz``) land: an example
runs from any folder, so it finds the URDFs that ship with hovi through the package
(``hovi.examples.models.urdf_path("two_link_arm")``), never through a path relative to the
repository (``models/...``). The code is compiled with the page's path and line numbers, so a
traceback points at the line of the Markdown file. Blocks that are not Python (shell commands,
layouts) are fenced with another language (```bash) or none and are not run; the checks below make
sure no Python hides in them and that the examples import nothing but numpy, hovi and the standard
library.
"""
import ast
import os
import re
import sys
import time
import traceback

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FENCE = re.compile(r"^(?P<indent>[ \t]*)(?P<fence>`{3,}|~{3,})[ \t]*(?P<info>[^\n`]*)$")
# Info strings that would hold Python but be skipped by a runner keyed on "python".
PYTHON_ALIASES = {"py", "py3", "python3", "pycon", "ipython", "ipython3"}
LOOKS_LIKE_PYTHON = re.compile(r"^\s*(import \w|from [\w.]+ import |\w+(, \w+)* = (hovi|np)\.)", re.M)
ALLOWED_IMPORTS = {"numpy", "hovi"} | set(getattr(sys, "stdlib_module_names", ()))


def pages():
    """README.md and every Markdown page under docs/, as paths relative to the repository root."""
    found = ["README.md"]
    for folder, _, files in os.walk(os.path.join(ROOT, "docs")):
        found += [os.path.relpath(os.path.join(folder, f), ROOT) for f in files if f.endswith(".md")]
    return sorted(found, key=lambda p: (p != "README.md", p))


def code_blocks(page):
    """[(language, first code line (1-based), code)] of the page's fenced code blocks, the code
    dedented by the fence's indentation (blocks inside lists and admonitions)."""
    lines = open(os.path.join(ROOT, page), encoding="utf-8").read().split("\n")
    blocks, i = [], 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        indent, fence = m["indent"], m["fence"]
        language = (m["info"].split() or [""])[0].lstrip(".").lower()
        close = re.compile(rf"^{re.escape(indent)}{re.escape(fence[0])}{{{len(fence)},}}[ \t]*$")
        j = i + 1
        while j < len(lines) and not close.match(lines[j]):
            j += 1
        assert j < len(lines), f"{page}:{i + 1}: code block never closed"
        body = [line[len(indent):] if line.startswith(indent) else line.lstrip() for line in lines[i + 1:j]]
        blocks.append((language, i + 2, "\n".join(body) + "\n"))
        i = j + 1
    return blocks


def python_blocks(page):
    return [(line, code) for language, line, code in code_blocks(page) if language == "python"]


PAGES_WITH_CODE = [p for p in pages() if python_blocks(p)]


def test_pages_have_examples():
    """The parser finds the examples: README and every tutorial have Python blocks to run."""
    tutorials = [p for p in pages() if p.startswith(os.path.join("docs", "tutorials"))]
    assert len(tutorials) >= 4, tutorials
    for page in ["README.md", os.path.join("docs", "getting-started.md")] + tutorials:
        assert page in PAGES_WITH_CODE, f"{page} has no ```python block"


@pytest.mark.parametrize("page", pages())
def test_no_python_escapes_the_runner(page):
    """Python is fenced as ```python (not py, python3, ... nor unlabelled), so that it is run here;
    and it imports only numpy, hovi and the standard library."""
    for language, line, code in code_blocks(page):
        where = f"{page}:{line - 1}"
        assert language not in PYTHON_ALIASES, f"{where}: fence it as ```python so that the test runs it"
        if language != "python":
            assert not LOOKS_LIKE_PYTHON.search(code), f"{where}: this ```{language} block looks like Python"
            continue
        for node in ast.walk(ast.parse(code, where)):
            names = ([a.name for a in node.names] if isinstance(node, ast.Import)
                     else [node.module or ""] if isinstance(node, ast.ImportFrom) and node.level == 0 else [])
            for name in names:
                assert name.split(".")[0] in ALLOWED_IMPORTS, f"{where}: imports {name} (only numpy, hovi, stdlib)"


@pytest.mark.parametrize("page", PAGES_WITH_CODE)
def test_examples_run(page, tmp_path, monkeypatch, capsys):
    """The page's ```python blocks run in order in one namespace without error (their asserts hold)."""
    monkeypatch.chdir(tmp_path)   # not the repository: nothing of it is found by a relative path
    namespace = {"__name__": "__main__"}
    start = time.perf_counter()
    for number, (line, code) in enumerate(python_blocks(page), 1):
        # leading newlines: tracebacks and asserts report the line of the Markdown file
        compiled = compile("\n" * (line - 1) + code, os.path.join(ROOT, page), "exec")
        try:
            exec(compiled, namespace)
        except Exception as e:
            error = "".join(traceback.format_exception(type(e), e, e.__traceback__.tb_next))  # from the page on
        else:
            continue
        pytest.fail(f"{page}, python block {number} (starting at line {line}) raised:\n{error}", pytrace=False)
    with capsys.disabled():
        print(f"\n  {page}: {number} blocks in {time.perf_counter() - start:.2f} s", end="")


def test_the_home_page_links_every_page_of_the_nav():
    """docs/index.md's table links every page of mkdocs.yml's nav (the tutorials and the top-level
    pages; the API reference through its first page), so a new page is not left out of it."""
    nav = re.findall(r"^\s*- [^:\n]+: (\S+\.md)\s*$", open(os.path.join(ROOT, "mkdocs.yml"), encoding="utf-8").read(), re.M)
    assert "tutorials/simulate.md" in nav and "reference/hovi.md" in nav, nav
    index = open(os.path.join(ROOT, "docs", "index.md"), encoding="utf-8").read()
    for page in nav:
        if page != "index.md" and not (page.startswith("reference/") and page != "reference/hovi.md"):
            assert f"]({page})" in index, f"docs/index.md does not link {page} (in mkdocs.yml's nav)"
