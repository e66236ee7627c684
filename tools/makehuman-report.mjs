// Writes docs/makehuman.md's comparison tables (between its makehuman-eval markers) from the JSON
// files of scripts/compare-makehuman.sh: `caliper eval` on the built-in body and on the MakeHuman
// body, per sex. Usage: node tools/makehuman-report.mjs DIR DOC.md
import fs from 'node:fs';
import path from 'node:path';

const [dir, docPath] = process.argv.slice(2);
if (!dir || !docPath) { console.error('usage: node tools/makehuman-report.mjs DIR DOC.md'); process.exit(2); }
const begin = '<!-- makehuman-eval:begin (scripts/compare-makehuman.sh) -->';
const end = '<!-- makehuman-eval:end -->';
const load = (sex, body) => JSON.parse(fs.readFileSync(path.join(dir, `${sex}-${body}.json`), 'utf8'));
const regressors = ['R2', 'R4', 'R5', 'R6'];
const inputs = ['stature', 'weight', 'span', 'crotchheight', 'hipbreadth', 'armlength'];
const f = x => Number(x).toFixed(2);
const mae = e => e.mae_cm ?? e.mae_kg;
// "built-in / MakeHuman" for one statistic, or '' where neither has it.
const pair = (a, b) => (a === undefined || b === undefined ? '' : `${f(a)} / ${f(b)}`);

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
    const cells = inputs.map(c => {
      const a = own.regressors[r].inputs[c], b = mh.regressors[r].inputs[c];
      return a && b ? pair(mae(a), mae(b)) : '';
    });
    p(`| ${r} | ${cells.join(' | ')} |`);
  }
  p();
  p(`**${who}, held-out accuracy** (avatar − ANSUR measurement, MAE in cm):`);
  p();
  const columns = [...new Set(regressors.flatMap(r => Object.keys(own.regressors[r].held_out)))].sort();
  p(`| measurement | ${regressors.join(' | ')} |`);
  p(`|---|${regressors.map(() => '---').join('|')}|`);
  for (const c of columns) {
    const cells = regressors.map(r => {
      const a = own.regressors[r].held_out[c], b = mh.regressors[r].held_out[c];
      return a && b ? pair(a.mae_cm, b.mae_cm) : '*input*';
    });
    p(`| ${c} | ${cells.join(' | ')} |`);
  }
  p();
  const share = (d, r) => `${(100 * d.regressors[r].implausible_share).toFixed(1)} %`;
  p(`Implausible avatars, ${who.toLowerCase()}, built-in / MakeHuman: ` +
    regressors.map(r => `${r} ${share(own, r)} / ${share(mh, r)}`).join(', ') + '.');
}
p();
p(end);

const doc = fs.readFileSync(docPath, 'utf8');
const i = doc.indexOf(begin), j = doc.indexOf(end);
if (i < 0 || j < i) { console.error(`${docPath}: the makehuman-eval markers are missing`); process.exit(1); }
fs.writeFileSync(docPath, doc.slice(0, i) + lines.join('\n') + doc.slice(j + end.length));
console.log(`wrote the comparison tables into ${docPath}`);
