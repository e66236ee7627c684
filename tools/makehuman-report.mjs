// Writes docs/makehuman.md's comparison tables (between its makehuman-eval markers) from the JSON
// files of scripts/compare-makehuman.sh: `caliper eval` on the built-in body and on the MakeHuman
// body, per sex. Usage: node tools/makehuman-report.mjs DIR DOC.md
import fs from 'node:fs';
import path from 'node:path';

const [dir, docPath] = process.argv.slice(2);
if (!dir || !docPath) { console.error('usage: node tools/makehuman-report.mjs DIR DOC.md'); process.exit(2); }
const begin = '<!-- makehuman-eval:begin (scripts/compare-makehuman.sh) -->';
const end = '<!-- makehuman-eval:end -->';
const regressors = ['R2', 'R4', 'R5', 'R6'];
const inputs = ['stature', 'weight', 'span', 'crotchheight', 'hipbreadth', 'armlength'];
function load(sex, body) {
  const file = path.join(dir, `${sex}-${body}.json`);
  const d = JSON.parse(fs.readFileSync(file, 'utf8'));
  for (const r of regressors)
    if (!d.regressors?.[r]?.inputs || !d.regressors[r].held_out) { console.error(`${file}: no results for ${r}`); process.exit(1); }
  return d;
}
// A statistic (null, as JSON writes NaN, or missing: '–').
const f = x => (typeof x === 'number' && Number.isFinite(x) ? x.toFixed(2) : '–');
const mae = e => e?.mae_cm ?? e?.mae_kg;
const pair = (a, b) => `${f(a)} / ${f(b)}`;  // built-in / MakeHuman

const lines = [begin, ''];
const p = (s = '') => lines.push(s);
p('Regenerate with `bash scripts/compare-makehuman.sh` (the ANSUR II development subset in `../shared`;');
p('`caliper eval --regressor R2,R4,R5,R6 --noise none --seed 1` on the built-in body and on the');
p('MakeHuman body built here, `build/makehuman-{female,male}.npz`). Each cell is built-in / MakeHuman.');
for (const sex of ['female', 'male']) {
  const own = load(sex, 'builtin'), mh = load(sex, 'makehuman');
  const who = sex === 'female' ? 'Women' : 'Men';
  p();
  p(`**${who} (${own.subjects.toLocaleString('en-US')}), Table 1 — inputs reproduced** (avatar − virtual input, MAE; cm, weight kg):`);
  p();
  p(`| regressor | ${inputs.join(' | ')} |`);
  p(`|---|${inputs.map(() => '---').join('|')}|`);
  for (const r of regressors) {
    // Blank where the regressor does not take that input.
    const cells = inputs.map(c => (c in own.regressors[r].inputs || c in mh.regressors[r].inputs
      ? pair(mae(own.regressors[r].inputs[c]), mae(mh.regressors[r].inputs[c])) : ''));
    p(`| ${r} | ${cells.join(' | ')} |`);
  }
  p();
  p(`**${who}, held-out accuracy** (avatar − ANSUR measurement, MAE in cm):`);
  p();
  const columns = [...new Set(regressors.flatMap(r => [own, mh].flatMap(d => Object.keys(d.regressors[r].held_out))))].sort();
  p(`| measurement | ${regressors.join(' | ')} |`);
  p(`|---|${regressors.map(() => '---').join('|')}|`);
  for (const c of columns) {
    // An input of the regressor is not held out; a value missing from one body shows as '–'.
    const cells = regressors.map(r => (c in own.regressors[r].inputs
      ? '*input*' : pair(mae(own.regressors[r].held_out[c]), mae(mh.regressors[r].held_out[c]))));
    p(`| ${c} | ${cells.join(' | ')} |`);
  }
  p();
  const share = (d, r) => {
    const x = d.regressors[r].implausible_share;
    return typeof x === 'number' ? `${(100 * x).toFixed(1)} %` : '–';
  };
  p(`Implausible avatars (rarer than 1 in 1,000 people of each model's population), ${who.toLowerCase()}, built-in / MakeHuman: ` +
    regressors.map(r => `${r} ${share(own, r)} / ${share(mh, r)}`).join(', ') + '.');
}
p();
p(end);

const doc = fs.readFileSync(docPath, 'utf8');
const i = doc.indexOf(begin), j = doc.indexOf(end);
if (i < 0 || j < i) { console.error(`${docPath}: the makehuman-eval markers are missing`); process.exit(1); }
fs.writeFileSync(docPath, doc.slice(0, i) + lines.join('\n') + doc.slice(j + end.length));
console.log(`wrote the comparison tables into ${docPath}`);
