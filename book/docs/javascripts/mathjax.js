// Formulas are typeset on the reader's side only when MathJax is present; without
// a network the page stays readable and shows the TeX source.
window.MathJax = {
  tex: { inlineMath: [["\\(", "\\)"]], displayMath: [["\\[", "\\]"]] },
  options: { processHtmlClass: "arithmatex" }
};
