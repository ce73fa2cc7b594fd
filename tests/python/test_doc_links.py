"""Relative links in README.md and docs/**/*.md resolve: the file exists in the source tree
(or is a page the docs build generates), and a #anchor names a heading of that page (the
GitHub/MyST slug of a level 1-3 heading, as myst_heading_anchors = 3 makes them)."""

import re

import pytest
from helpers import ROOT, needs_source

LINK = re.compile(r"(?<!!)\[[^\]]*\]\(([^)\s]+)\)|!\[[^\]]*\]\(([^)\s]+)\)")
FENCE = re.compile(r"^(```|~~~).*?^\1\s*$", re.S | re.M)
# pages docs/conf.py writes when the build starts (tools/docs_gallery.py), not in git
GENERATED = {"docs/api/index.rst", "docs/gallery/index.md", "docs/guide/ensembles.md"}


def _pages():
    skip = ("_build", "_generated", "gallery", "api")
    return [ROOT / "README.md"] + sorted(
        p for p in (ROOT / "docs").rglob("*.md") if not set(p.relative_to(ROOT / "docs").parts) & set(skip)
    )


def _slug(heading):
    """GitHub-style anchor of a heading: lower case, punctuation dropped, spaces to -."""
    text = re.sub(r"[`*_]", "", heading.strip().lower())
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def _anchors(page):
    text = FENCE.sub("", page.read_text())
    return {_slug(m.group(2)) for m in re.finditer(r"^(#{1,3})\s+(.*)$", text, re.M)}


def _links(page):
    text = FENCE.sub("", page.read_text())
    text = re.sub(r"`[^`\n]*`", "", text)  # inline code is not a link
    for m in LINK.finditer(text):
        target = m.group(1) or m.group(2)
        if not re.match(r"^[a-z][a-z+.-]*:", target):  # http:, https:, mailto: ... left alone
            yield target


@needs_source
@pytest.mark.parametrize("page", _pages(), ids=lambda p: str(p.relative_to(ROOT)))
def test_relative_links_resolve(page):
    bad = []
    for target in _links(page):
        path, _, anchor = target.partition("#")
        dest = (page.parent / path).resolve() if path else page
        rel = dest.relative_to(ROOT).as_posix() if dest.is_relative_to(ROOT) else str(dest)
        alt = {rel, rel[:-3] + ".rst"} if rel.endswith(".md") else {rel}
        if not dest.exists() and not alt & GENERATED:
            bad.append(f"{target}: no such file")
        elif anchor and dest.suffix == ".md" and dest.exists() and anchor not in _anchors(dest):
            bad.append(f"{target}: no heading with anchor #{anchor}")
    assert not bad, f"{page.relative_to(ROOT)}: " + "; ".join(bad)


def test_the_link_pattern_finds_links():
    page_text = "See [the guide](docs/guide/linear.md#api), ![fig](a.png) and [web](https://x.org)."
    found = [m.group(1) or m.group(2) for m in LINK.finditer(page_text)]
    assert found == ["docs/guide/linear.md#api", "a.png", "https://x.org"]
    assert (
        _slug("Linear damping: pendula, the text's formulas and `expm`")
        == "linear-damping-pendula-the-texts-formulas-and-expm"
    )
