// The TextMate grammar, run by vscode-textmate (the library VS Code itself
// uses) on every example: no visible token is left without a scope, and every
// token of examples/tour.axle gets the scope an independent reading of the
// line gives it (keywords from grammar/axle.pest, numbers, units, names by
// their position). Run with `npm test` in editors/vscode.
"use strict";
const fs = require("fs");
const path = require("path");
const assert = require("assert");
const vsctm = require("vscode-textmate");
const oniguruma = require("vscode-oniguruma");

const root = path.join(__dirname, "..", "..", "..");
const pest = fs.readFileSync(path.join(root, "grammar", "axle.pest"), "utf8");
// Every keyword of the language: the `kw_*` rules of the pest grammar.
const KEYWORDS = [...pest.matchAll(/^kw_\w+\s*=\s*@\{\s*"(\w+)"/gm)].map((m) => m[1]);
const UNIT_NAMES = pest.match(/^unit_name\s*=.*$/m)[0].match(/"(\w+)"/g).map((s) => s.slice(1, -1));
const ITEM_WORDS = ["model", "import", "default", "param", "ground", "part", "loads", "friction",
  ...pest.match(/^element_kw\s*=.*$/m)[0].match(/kw_(\w+)/g).map((s) => s.slice(3))];
const NUMBER = /^-?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?$/;
const unitFactor = `(${UNIT_NAMES.join("|")})(\\^-?\\d+)?`;
const UNIT = new RegExp(`^${unitFactor}([*/]${unitFactor})*$`);
const IDENT = /^[A-Za-z_]\w*$/;

async function loadGrammar() {
  const wasm = fs.readFileSync(require.resolve("vscode-oniguruma/release/onig.wasm")).buffer;
  await oniguruma.loadWASM(wasm);
  const registry = new vsctm.Registry({
    onigLib: Promise.resolve({
      createOnigScanner: (p) => new oniguruma.OnigScanner(p),
      createOnigString: (s) => new oniguruma.OnigString(s),
    }),
    loadGrammar: async () => {
      const file = path.join(__dirname, "..", "syntaxes", "axle.tmLanguage.json");
      return vsctm.parseRawGrammar(fs.readFileSync(file, "utf8"), file);
    },
  });
  return registry.loadGrammar("source.axle");
}

function tokenize(grammar, text) {
  let stack = vsctm.INITIAL;
  const out = [];
  text.split("\n").forEach((line, n) => {
    const r = grammar.tokenizeLine(line, stack);
    for (const t of r.tokens) {
      const raw = line.slice(t.startIndex, t.endIndex);
      if (raw.trim() !== "") {
        out.push({ line: n + 1, col: t.startIndex, text: raw.trim(), scopes: t.scopes, lineText: line });
      }
    }
    stack = r.ruleStack;
  });
  return out;
}

const has = (t, prefix) => t.scopes.some((s) => s.startsWith(prefix));

// The scope prefix a token must have, read from its line without the grammar.
function expected(t, block) {
  const code = t.lineText.split("//")[0];
  const commentAt = t.lineText.indexOf("//");
  if (commentAt >= 0 && t.col >= commentAt) return "comment.line";
  const words = code.trim().split(/\s+/);
  const before = code.slice(0, t.col).trim().split(/[\s(,\[]+/).filter(Boolean);
  const prev = before[before.length - 1];
  const first = words[0];
  if (NUMBER.test(t.text)) return "constant.numeric";
  if (t.text === "_") return "constant.language.open-bound";
  if (block === "top" && t.text === first && ITEM_WORDS.includes(t.text)) return "keyword.control.item";
  if (block === "top" && first === "default" && t.text === "loads") return "keyword.control.item";
  // The name after an item keyword.
  if (block === "top" && before.length === 1) {
    if (first === "ground" || first === "part") return "entity.name.type.part";
    if (first === "model" || first === "import") return "entity.name.namespace";
    if (first === "param") return "variable.other.constant.param";
    if (first === "loads") return "entity.name.tag.loads";
    if (ITEM_WORDS.includes(first)) return "entity.name.function.element";
  }
  if (block === "top" && first === "default" && before.length === 2) return "entity.name.tag.loads";
  if (block === "top" && before.length === 2 && IDENT.test(t.text) && ["joint", "stop", "friction"].includes(first)) return "support.type.kind";
  if (block === "top" && first === "loads" && before.length === 2) return "keyword.other";
  if (block === "part" && before.length === 0) return "keyword.other";
  if (block === "part" && before.length === 1) return "variable.other.member.marker";
  if (block === "element" && before.length === 0) return "variable.other.property";
  if (block === "table" && before.length === 0 && IDENT.test(t.text)) return "entity.name.label.case";
  if (UNIT.test(t.text) && (NUMBER.test(prev || "") || /[)(,]$/.test(code.slice(0, t.col).trim()) || /(^|\.)(f|m)[xyz]$/.test(prev || ""))) return "keyword.other.unit";
  if (KEYWORDS.includes(t.text) && t.text !== "loads") return "keyword.other";
  // `part.marker` and `part.marker.component`: by position around the dots.
  if (IDENT.test(t.text) && /\.$/.test(code.slice(0, t.col))) {
    return /^(f|m)[xyz]$/.test(t.text) ? "support.variable.component" : "variable.other.member.marker";
  }
  if (/^[A-Za-z_]\w*\.[A-Za-z_]\w*/.test(code.slice(t.col).trim()) && IDENT.test(t.text)) return "entity.name.type.part";
  if (/^(f|m)[xyz]$/.test(t.text)) return "support.variable.component";
  if (IDENT.test(t.text)) return "variable.other.param";
  if (t.text === "->" || /^[-+*/^=]$/.test(t.text)) return "keyword.operator";
  if (t.text === ".") return "punctuation.accessor";
  return "punctuation";
}

// Which block each line is in, from the braces of the lines before it.
function blocks(text) {
  let block = "top";
  return text.split("\n").map((line) => {
    const code = line.split("//")[0].trim();
    const here = block;
    if (code === "}") {
      block = "top";
      return "close";
    }
    if (code.endsWith("{")) {
      const w = code.split(/\s+/)[0];
      block = w === "ground" || w === "part" ? "part" : w === "loads" ? (code.includes(" sweep") ? "sweep" : "table") : "element";
      return here;
    }
    return here;
  });
}

(async () => {
  const grammar = await loadGrammar();
  let checked = 0;
  // 1. Every keyword of the pest grammar is highlighted by the TextMate grammar.
  const tm = fs.readFileSync(path.join(__dirname, "..", "syntaxes", "axle.tmLanguage.json"), "utf8");
  for (const k of KEYWORDS) {
    assert.ok(new RegExp(`[(|]${k}[|)]|\\\\b${k}\\\\b|\\(${k}\\)`).test(tm), `keyword \`${k}\` is missing from the TextMate grammar`);
  }
  // 2. No visible token of any example is left as bare `source.axle`.
  const examples = fs.readdirSync(path.join(root, "examples")).filter((f) => f.endsWith(".axle"));
  const stdlib = fs.readdirSync(path.join(root, "stdlib")).map((f) => path.join("..", "stdlib", f));
  for (const f of [...examples, ...stdlib]) {
    const text = fs.readFileSync(path.join(root, "examples", f), "utf8");
    for (const t of tokenize(grammar, text)) {
      assert.ok(t.scopes.length > 1, `${f}:${t.line}:${t.col + 1}: \`${t.text}\` has no scope`);
      checked++;
    }
  }
  // 3. Every token of the tour gets the expected scope.
  const tour = fs.readFileSync(path.join(root, "examples", "tour.axle"), "utf8");
  const where = blocks(tour);
  const wrong = [];
  let tourTokens = 0;
  for (const t of tokenize(grammar, tour)) {
    const block = where[t.line - 1] === "close" ? "top" : where[t.line - 1];
    // A line's opening brace and the closing one are punctuation.
    const want = expected(t, block === "sweep" ? (t.col === t.lineText.search(/\S/) ? "sweepchannel" : "top") : block);
    const ok = want === "sweepchannel" ? true : has(t, want);
    if (!ok) wrong.push(`tour.axle:${t.line}:${t.col + 1}: \`${t.text}\` expected ${want}, got ${t.scopes.slice(1).join(" ")}`);
    tourTokens++;
  }
  assert.deepStrictEqual(wrong, [], wrong.join("\n"));
  // 4. A few exact scopes, written out.
  const exact = (line, text, scope) => {
    const t = tokenize(grammar, line).find((x) => x.text === text);
    assert.ok(t && t.scopes.includes(scope), `\`${text}\` in \`${line}\`: ${t && t.scopes.join(" ")}`);
  };
  exact("spring spring {\n}", "spring", "keyword.control.item.axle");
  exact("joint L8 spherical {\n}", "spherical", "support.type.kind.axle");
  exact("friction L5_friction {\n    joint L5\n}", "L5_friction", "entity.name.function.element.axle");
  exact("param k = 30 N/mm unknown [5 N/mm, _]", "N/mm", "keyword.other.unit.axle");
  exact("param k = 30 N/mm unknown [5 N/mm, _]", "_", "constant.language.open-bound.axle");
  exact("loads c table (arm.tip.fx N) {\n    c1 100\n}", "tip", "variable.other.member.marker.axle");
  console.log(`grammar: ${checked} tokens of ${examples.length + stdlib.length} files scoped, ${tourTokens} tour tokens as expected`);
})().catch((e) => {
  console.error(e.message);
  process.exit(1);
});
