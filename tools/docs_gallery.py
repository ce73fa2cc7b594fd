"""Pages of the documentation that are generated, not written: the Python API list
(from pendula.__all__) and the example gallery (each examples/python/*.py run in
quick mode, its console output and figures shown beside its source).

Called by docs/conf.py when Sphinx starts; the pages land in docs/api/ and
docs/gallery/, which are build output (ignored by git).
"""

import ast
import os
import pathlib
import subprocess
import sys
import time

# run_all.py drives the others (and the benchmarks): it is not an example of its own.
SKIP = {"run_all.py"}


def write_api_list(path):
    """docs/api/index.rst: one autosummary entry, hence one page, per public name."""
    import pendula

    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    names = sorted(pendula.__all__, key=str.lower)
    lines = [
        "Python API",
        "==========",
        "",
        "Every name in ``pendula.__all__``, one page each, generated from the docstrings.",
        "Angles are in radians, angular speeds in rad/s, times in s, ``w0`` in 1/s.",
        "",
        ".. currentmodule:: pendula",
        "",
        ".. autosummary::",
        "   :toctree: generated",
        "",
    ]
    lines += [f"   {n}" for n in names]
    text = "\n".join(lines) + "\n"
    if not path.exists() or path.read_text() != text:
        path.write_text(text)


def write_ensembles_slot(page, source):
    """docs/guide/ensembles.md: the ensembles guide (docs/ensembles.md) when it exists."""
    page = pathlib.Path(page)
    if pathlib.Path(source).exists():
        text = "```{include} ../ensembles.md\n```\n"
    else:
        text = "# Ensembles\n\nThe guide to ensembles of initial states is not written yet.\n"
    if not page.exists() or page.read_text() != text:
        page.write_text(text)


def _docstring(script):
    doc = ast.get_docstring(ast.parse(script.read_text())) or script.stem
    first, _, rest = doc.partition("\n")
    return first.strip().rstrip("."), rest.strip()


def _run(script, out):
    """Run one example into out/ (quick mode when it has one); return (console text, seconds)."""
    out.mkdir(parents=True, exist_ok=True)
    cmd = [sys.executable, str(script), "--out", str(out)]
    if "--quick" in script.read_text():
        cmd.append("--quick")
    env = dict(os.environ, MPLBACKEND="Agg")
    start = time.perf_counter()
    proc = subprocess.run(cmd, cwd=str(out), env=env, capture_output=True, text=True, timeout=600)
    took = time.perf_counter() - start
    if proc.returncode != 0:
        raise RuntimeError(f"example {script.name} failed ({proc.returncode}):\n{proc.stderr}")
    return proc.stdout, took


def _page(script, out, console):
    title, body = _docstring(script)
    rel = os.path.relpath(script, out.parent.parent)
    parts = [f"# {title}", "", f"`examples/python/{script.name}`", ""]
    if body:
        parts += ["```text", body, "```", ""]
    figures = sorted(out.glob("*.png"))
    if figures:
        parts += ["## Figures", ""]
        for fig in figures:
            parts += [f"```{{image}} _out/{script.stem}/{fig.name}", f":alt: {fig.stem}", "```", ""]
    if console.strip():
        parts += ["## Output (quick mode)", "", "```text", console.rstrip(), "```", ""]
    tables = sorted(p.name for p in out.glob("*.csv"))
    if tables:
        parts += ["Tables written with `--out`: " + ", ".join(f"`{t}`" for t in tables) + ".", ""]
    parts += ["## Source", "", f"```{{literalinclude}} {rel}", ":language: python", "```", ""]
    return "\n".join(parts)


def write_gallery(gallery, examples):
    """docs/gallery/: an index and one page per example script, each run afresh."""
    gallery = pathlib.Path(gallery)
    gallery.mkdir(parents=True, exist_ok=True)
    # a leading underscore marks a module the examples share, not an example
    scripts = sorted(
        p for p in pathlib.Path(examples).glob("*.py") if p.name not in SKIP and not p.name.startswith("_")
    )
    total = 0.0
    for script in scripts:
        out = gallery / "_out" / script.stem
        console, took = _run(script, out)
        total += took
        (gallery / f"{script.stem}.md").write_text(_page(script, out, console))
    index = [
        "# Example gallery",
        "",
        "Each example script of `examples/python/`, run in quick mode while the documentation",
        "is built (`python examples/python/NAME.py --out DIR` runs the full version).",
        "",
        "```{toctree}",
        ":maxdepth: 1",
        "",
    ]
    index += [s.stem for s in scripts] + ["```", ""]
    (gallery / "index.md").write_text("\n".join(index))
    print(f"docs gallery: {len(scripts)} examples run in {total:.1f} s")


def write_gallery_placeholder(gallery):
    """docs/gallery/index.md when the examples are not run (PENDULA_DOCS_GALLERY=skip): the
    index the table of contents points to, saying so (pages of an earlier run are kept)."""
    index = pathlib.Path(gallery) / "index.md"
    if index.exists():
        return
    index.parent.mkdir(parents=True, exist_ok=True)
    index.write_text(
        "# Example gallery\n\nThis build skipped running the examples "
        "(`PENDULA_DOCS_GALLERY=skip`); the scripts are in `examples/python/`.\n"
    )
