// MathJax 3 typesets what pymdownx.arithmatex (generic mode) marks: \( \) inline and \[ \] displayed, inside
// elements of class "arithmatex" only. SVG output draws its glyphs from the script itself: no font files to load,
// so the site typesets its formulas when opened from disk, with no network.
window.MathJax = {
  tex: {
    inlineMath: [["\\(", "\\)"]],
    displayMath: [["\\[", "\\]"]],
    processEscapes: true,
    processEnvironments: true,
  },
  options: {
    ignoreHtmlClass: ".*|",
    processHtmlClass: "arithmatex",
  },
  svg: { fontCache: "global" },
};
