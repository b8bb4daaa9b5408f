"""Formulas typeset when the book is built, as MathML, which browsers draw themselves:
no script, no network, nothing to wait for. pymdownx.arithmatex finds the formulas;
this hook turns each into a <math> element (course_tools/editions/formulas.py, which
the starters' pages use too). A formula that does not convert is logged as an error
naming the page and the formula, which fails `mkdocs build --strict` (./course book);
without --strict the page keeps the TeX."""

from __future__ import annotations

import html
import re

from mkdocs.plugins import get_plugin_logger

from course_tools.editions.formulas import FORMULA, FormulaError, to_mathml

log = get_plugin_logger("mathml")


def on_page_content(content: str, page, config, files) -> str:
    def typeset(match: re.Match) -> str:
        display = match["block"] is not None
        tex = html.unescape(match["block"] if display else match["inline"])
        try:
            mathml = to_mathml(tex, display)
        except FormulaError as error:
            log.error(f"{page.file.src_uri}: the formula \"{' '.join(tex.split())}\" "
                      f"cannot be typeset: {error}")
            return match[0]
        return match["open"] + mathml + match["close"]

    return FORMULA.sub(typeset, content)
