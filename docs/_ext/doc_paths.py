"""Make every mention of a guide page by its path (``docs/errors.md``) a link to it.

The guide's Markdown and the code's docstrings name the contracts by their file in the
repository, which is what a reader of the source sees; on the site such a mention links
to the page built from that file.  A path that names no page of the site stays text.
"""

from __future__ import annotations

import re
from typing import Any

from docutils import nodes

PATH = re.compile(r"docs/([a-z0-9-]+)\.md")


def _linked(text: str, docname: str, app: Any, pages: set[str]) -> list[nodes.Node] | None:
    """The text split into text and links; None when it mentions no page."""
    parts: list[nodes.Node] = []
    last = 0
    for match in PATH.finditer(text):
        if match.group(1) not in pages:
            continue
        parts.append(nodes.Text(text[last:match.start()]))
        uri = app.builder.get_relative_uri(docname, match.group(1))
        parts.append(nodes.reference(match.group(0), match.group(0), refuri=uri,
                                     internal=True))
        last = match.end()
    if not parts:
        return None
    parts.append(nodes.Text(text[last:]))
    return parts


def _link_paths(app: Any, doctree: Any, docname: str) -> None:
    if app.builder.format != "html":
        return
    pages = set(app.env.found_docs)
    for node in list(doctree.findall(nodes.Text)):
        parent = node.parent
        if parent is None or isinstance(parent, (nodes.reference, nodes.literal_block,
                                                 nodes.literal, nodes.raw)):
            continue
        if isinstance(parent.parent, nodes.reference):
            continue
        parts = _linked(node.astext(), docname, app, pages)
        if parts is None:
            continue
        parent.replace(node, parts)


def setup(app: Any) -> dict[str, Any]:
    """Register the transform (after references are resolved)."""
    app.connect("doctree-resolved", _link_paths)
    return {"parallel_read_safe": True, "version": "1"}
