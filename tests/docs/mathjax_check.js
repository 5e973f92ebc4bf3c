// Typeset TeX formulas with MathJax 3 (the copy the documentation site ships) and report the ones it cannot read.
// Usage: node mathjax_check.js ES5_DIR < formulas.json, where formulas.json is a JSON list of [tex, display] pairs;
// prints a JSON list of [tex, message].  Unlike the site's script (which shows a bad formula in red), an undefined
// command or a syntax error is an error here, named by MathJax's own message.
const dir = process.argv[2];
let input = "";
process.stdin.on("data", (d) => (input += d));
process.stdin.on("end", () => {
  require(dir + "/node-main.js")
    .init({
      loader: { paths: { mathjax: dir }, load: ["input/tex-full", "adaptors/liteDOM", "output/svg"], versionWarnings: false },
      tex: { packages: { "[-]": ["noundefined", "noerrors"] }, formatError: (jax, err) => { throw err; } },
    })
    .then((MathJax) => {
      const errors = [];
      for (const [tex, display] of JSON.parse(input)) {
        try {
          const svg = MathJax.startup.adaptor.outerHTML(MathJax.tex2svg(tex, { display }));
          if (/data-mjx-error|data-mml-node="merror"/.test(svg)) errors.push([tex, "shown as an error"]);
        } catch (e) {
          errors.push([tex, e.message]);
        }
      }
      console.log(JSON.stringify(errors));
    })
    .catch((e) => {
      console.error(e.message);
      process.exit(1);
    });
});
