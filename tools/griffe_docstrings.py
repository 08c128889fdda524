"""A griffe extension for the docs site: the package's docstrings, written for ``help()`` and
Sphinx habits, rendered as clean Markdown by mkdocstrings (mkdocs.yml loads it).

- doctest runs (``>>>`` lines with their ``...`` continuations and output) become fenced
  ``pycon`` blocks, so Markdown does not read ``>>>`` as nested quotes or ``[..][..]`` as a
  link;
- Sphinx roles (``:class:`~skydome.scene.Sky```, ``:func:`f```, ``:mod:`m```, …) become code
  spans (the name as shown by Sphinx: the last component when ``~`` is given);
- a paragraph ending in ``::`` (reST's literal-block marker) ends in ``:``;
- an argument entry naming several parameters (``a, b: what they are``) becomes one entry
  per parameter, the later ones pointing to the first, so each gets its type and default;
- parameters whose names start with ``_`` (private plumbing) leave the signatures.

The source is not changed; only the text griffe hands to mkdocstrings.
"""

from __future__ import annotations

import re

import griffe

_ROLE = re.compile(r":(?:class|func|meth|mod|data|attr|obj|exc|const):`(~?)([^`]+)`")


def _role(match: re.Match) -> str:
    tilde, target = match.groups()
    return f"`{target.rsplit('.', 1)[-1] if tilde else target}`"


def fence_doctests(text: str) -> str:
    """``text`` with each run of doctest lines (a ``>>>`` line, its ``...`` continuations and
    the output up to a blank line) inside a ```` ```pycon ```` fence at its indentation."""
    lines = text.split("\n")
    out: list[str] = []
    i = 0
    while i < len(lines):
        stripped = lines[i].lstrip()
        if not stripped.startswith(">>>"):
            out.append(lines[i])
            i += 1
            continue
        indent = lines[i][: len(lines[i]) - len(stripped)]
        if out and out[-1].strip():
            out.append("")
        out.append(f"{indent}```pycon")
        while i < len(lines) and lines[i].strip() and lines[i].startswith(indent):
            out.append(lines[i])
            i += 1
        out.append(f"{indent}```")
        if i < len(lines) and lines[i].strip():
            out.append("")
    return "\n".join(out)


_SHARED_ARG = re.compile(r"^(\s+)(\w+(?:, \w+)+): (.*)$")


def split_shared_args(text: str) -> str:
    """``text`` with each Google-style argument line ``a, b: text`` (and its indented
    continuation lines) written as ``a: text`` followed by ``b: the same as `a`.``"""
    lines = text.split("\n")
    out: list[str] = []
    i = 0
    while i < len(lines):
        m = _SHARED_ARG.match(lines[i])
        if m is None:
            out.append(lines[i])
            i += 1
            continue
        indent, names, first = m.group(1), m.group(2).split(", "), m.group(3)
        out.append(f"{indent}{names[0]}: {first}")
        i += 1
        while i < len(lines) and lines[i].startswith(indent + " ") and lines[i].strip():
            out.append(lines[i])
            i += 1
        out += [f"{indent}{name}: the same as `{names[0]}`." for name in names[1:]]
    return "\n".join(out)


def markdown_docstring(text: str) -> str:
    """The docstring ``text`` as Markdown (see the module docstring)."""
    text = split_shared_args(fence_doctests(text))
    text = _ROLE.sub(_role, text)
    return re.sub(r"(\S)::$", r"\1:", text, flags=re.MULTILINE)


class MarkdownDocstrings(griffe.Extension):
    """Rewrite every object's docstring with :func:`markdown_docstring` when it is loaded."""

    def on_object(self, *, obj: griffe.Object, **kwargs) -> None:
        if obj.docstring is not None:
            obj.docstring.value = markdown_docstring(obj.docstring.value)
        if isinstance(obj, griffe.Function):
            for name in [p.name for p in obj.parameters if p.name.startswith("_")]:
                del obj.parameters[name]
