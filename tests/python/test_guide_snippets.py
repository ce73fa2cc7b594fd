"""The guides' Python snippets cannot rot: every ```python block of docs/*.md and
docs/guide/*.md written as a doctest (with >>>) runs and must print what the page shows
(one namespace per page, top to bottom, as a reader would type them);
every other Python block (illustrations: a cluster, files written, long runs) must at least
parse. The guides that teach the Python API each keep at least one doctested block."""

import doctest
import re

import pytest
from helpers import ROOT, needs_source

import pendula  # noqa: F401  (the snippets import it themselves; fail early if it is missing)

BLOCK = re.compile(r"^```python\n(.*?)^```", re.S | re.M)
# guides whose Python examples must be checked by running them, not only by reading them
DOCTESTED = [
    "guide/elliptic.md",
    "guide/undamped.md",
    "guide/linear.md",
    "guide/integrators.md",
    "guide/scenes.md",
    "guide/fitting.md",
    "guide/driven.md",
]


def _pages():
    docs = ROOT / "docs"
    return sorted(
        p
        for p in list(docs.glob("*.md")) + list(docs.glob("guide/*.md"))
        if p.name != "ensembles.md" or p.parent == docs
    )  # guide/ensembles.md is a copy


def _blocks(page):
    return BLOCK.findall(page.read_text())


# optional extras a snippet may use: without them its page is skipped, not failed
OPTIONAL = {"plot_": "matplotlib", "to_pandas": "pandas", "to_xarray": "xarray"}

PAGES = _pages() if (ROOT / "docs").is_dir() else []


@needs_source
@pytest.mark.parametrize("page", PAGES, ids=lambda p: str(p.relative_to(ROOT / "docs")))
def test_guide_python_blocks(page, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # a snippet that writes a file writes it here
    for marker, module in OPTIONAL.items():
        if any(">>>" in b and marker in b for b in _blocks(page)):
            pytest.importorskip(module)
    failures, namespace = 0, {}
    for number, block in enumerate(_blocks(page)):
        name = f"{page.name} block {number}"
        if ">>>" not in block:
            compile(block, name, "exec")  # a SyntaxError names the page and block
            continue
        test = doctest.DocTestParser().get_doctest(block, namespace, name, str(page), 0)
        test.globs = namespace  # get_doctest copies it; share it across blocks
        runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
        runner.run(test, clear_globs=False)
        failures += runner.failures
    assert failures == 0, f"{page.name}: a Python example no longer gives what the page shows"


@needs_source
@pytest.mark.parametrize("name", DOCTESTED)
def test_api_guides_keep_a_doctest(name):
    blocks = _blocks(ROOT / "docs" / name)
    assert any(">>>" in b and len(doctest.DocTestParser().get_examples(b)) >= 2 for b in blocks)
