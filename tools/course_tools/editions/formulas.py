"""TeX formulas as MathML, checked: the book's hook (book/hooks/mathml.py) and the
starters' pages (editions.render_page) typeset with this.

pymdownx.arithmatex (generic mode) finds the formulas and keeps Markdown away from them;
it leaves each one as TeX, `\\( … \\)` in a <span class="arithmatex"> or `\\[ … \\]` in a
<div class="arithmatex">; to_mathml turns one into a <math> element with latex2mathml.

latex2mathml does not complain about everything it cannot do: an unknown macro comes out
as the text "\\foo", a missing brace as a fraction with one part, an `&` outside a
matrix as broken XML. So its output is checked too: to_mathml raises FormulaError,
saying what is wrong, rather than return a formula drawn wrong."""

from __future__ import annotations

import html
import re
import xml.etree.ElementTree as ElementTree

from latex2mathml.converter import convert

# arithmatex's generic output (tex_inline_wrap and tex_block_wrap left at their defaults).
FORMULA = re.compile(r'(?P<open><(?P<tag>span|div) class="arithmatex">)'
                     r'(?:\\\((?P<inline>.*?)\\\)|\\\[(?P<block>.*?)\\\])'
                     r'(?P<close></(?P=tag)>)', re.S)

MATHML = "{http://www.w3.org/1998/Math/MathML}"
# Elements whose children are fixed in number: anything else is a formula latex2mathml
# misread (\frac{a} without its second part gives an <mfrac> of one child).
ARITY = {"mfrac": 2, "msub": 2, "msup": 2, "msubsup": 3, "munder": 2, "mover": 2,
         "munderover": 3, "mroot": 2}
# latex2mathml writes \cos as a plain <mi>cos</mi>, which a browser sets against what
# follows ("cosθ"); TeX puts a thin space there, unless a bracket follows.
FUNCTION_NAME = re.compile(r"(<mi>(?:sin|cos|tan|cot|sec|csc|log|ln|exp)</mi>)"
                           r"(?!<mo[^>]*>(?:\(|&#x00028;))")
THIN_SPACE = '<mspace width="0.167em" />'


class FormulaError(ValueError):
    pass


def to_mathml(tex: str, display: bool) -> str:
    """The <math> element of one formula; FormulaError says what is wrong with it."""
    depth = 0
    for i, char in enumerate(tex):
        escaped = i > 0 and tex[i - 1] == "\\"
        if char == "{" and not escaped:
            depth += 1
        elif char == "}" and not escaped:
            depth -= 1
            if depth < 0:
                raise FormulaError("a '}' closes nothing")
    if depth:
        raise FormulaError(f"{depth} '{{' never closed")
    try:
        mathml = convert(tex.strip(), display="block" if display else "inline")
    except Exception as error:  # latex2mathml raises a dozen kinds, StopIteration too
        raise FormulaError(f"latex2mathml: {type(error).__name__} {error}".strip()) from None
    try:
        root = ElementTree.fromstring(mathml)
    except ElementTree.ParseError as error:
        raise FormulaError(f"the MathML is not well-formed ({error}): an '&' or '\\\\' "
                           "outside an environment latex2mathml knows?") from None
    for element in root.iter():
        name = element.tag.removeprefix(MATHML)
        if name in ARITY and len(element) != ARITY[name]:
            raise FormulaError(f"<{name}> has {len(element)} parts, not {ARITY[name]}: "
                               "a missing argument?")
        if "\\" in (element.text or ""):
            raise FormulaError(f"latex2mathml does not know {element.text.strip()}")
    mathml = FUNCTION_NAME.sub(lambda name: name[1] + THIN_SPACE, mathml)
    # The TeX stays with the formula for screen readers and for copying.
    return mathml.replace("<math ", f'<math alttext="{html.escape(tex.strip())}" ', 1)
