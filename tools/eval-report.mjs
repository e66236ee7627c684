// Writes docs/evaluation.md and its SVG plots from the JSON files of scripts/evaluate.sh.
// Usage: node tools/eval-report.mjs DIR OUT.md
import fs from 'node:fs';
import path from 'node:path';

const [dir, outMd] = process.argv.slice(2);
if (!dir || !outMd) { console.error('usage: node tools/eval-report.mjs DIR OUT.md'); process.exit(2); }
const load = (sex, noise) => JSON.parse(fs.readFileSync(path.join(dir, `${sex}-${noise}.json`), 'utf8'));
const sexes = ['female', 'male'];
const noises = ['none', 'self', 'other'];
const R = ['R2', 'R4', 'R5', 'R6', 'auto'];
const heldOut = ['chestcircumference', 'waistcircumference', 'buttockcircumference', 'thighcircumference',
  'calfcircumference', 'biacromialbreadth', 'chestbreadth', 'chestdepth', 'waistbreadth', 'waistdepth',
  'acromialheight', 'waistheightomphalion'];
// The linear limit of each method (`caliper eval`): least squares from the method's own
// inputs straight to each column, cross-validated over the same subjects. auto's uses all six.
const linearOf = (d, c) => d.regressors.auto?.linear_limit?.[c]?.mae_cm;
const f = (x, d = 2) => (x === undefined || x === null ? '–' : Number(x).toFixed(d));
const lines = [];
const p = (s = '') => lines.push(s);

function barChart(sex, data) {
  // Held-out MAE (cm) per column, one bar per method.
  const methods = [...R, 'uniform'];
  const colours = { R2: '#9bb7d4', R4: '#5b8db8', R5: '#2f5f8a', R6: '#1a3550', auto: '#27ae60', uniform: '#d9a441' };
  const W = 1100, rowH = 30, top = 40, left = 190, H = top + heldOut.length * rowH + 40;
  const max = Math.max(...heldOut.flatMap(c => methods.map(m => (m === 'uniform'
    ? data.baselines.uniform_scale.held_out[c].mae_cm : data.regressors[m].held_out[c].mae_cm))));
  const scale = (W - left - 160) / max;
  let svg = `<svg xmlns="http://www.w3.org/2000/svg" width="${W}" height="${H}" font-family="sans-serif" font-size="12">`;
  svg += `<rect width="100%" height="100%" fill="white"/><text x="10" y="20" font-size="14">Held-out MAE (cm), ${sex}, ANSUR II development subset, no added noise</text>`;
  heldOut.forEach((c, i) => {
    const y = top + i * rowH;
    svg += `<text x="${left - 8}" y="${y + 15}" text-anchor="end">${c}</text>`;
    methods.forEach((m, j) => {
      const v = m === 'uniform' ? data.baselines.uniform_scale.held_out[c].mae_cm : data.regressors[m].held_out[c].mae_cm;
      svg += `<rect x="${left}" y="${y + j * 4 + 2}" width="${(v * scale).toFixed(1)}" height="4" fill="${colours[m]}"/>`;
    });
    const lin = linearOf(data, c);
    svg += `<line x1="${left + lin * scale}" x2="${left + lin * scale}" y1="${y}" y2="${y + 22}" stroke="#c0392b" stroke-width="2"/>`;
  });
  const ly = top + heldOut.length * rowH + 15;
  methods.forEach((m, j) => {
    svg += `<rect x="${left + j * 110}" y="${ly}" width="12" height="12" fill="${colours[m]}"/><text x="${left + j * 110 + 16}" y="${ly + 11}">${m === 'uniform' ? 'uniform scale' : m}</text>`;
  });
  svg += `<line x1="${left + 680}" x2="${left + 680}" y1="${ly}" y2="${ly + 12}" stroke="#c0392b" stroke-width="2"/><text x="${left + 686}" y="${ly + 11}">linear limit (6 inputs)</text>`;
  return svg + '</svg>\n';
}

p('# Evaluation');
p();
p('How accurate are Caliper\'s avatars? Regenerate everything on this page with');
p('`bash scripts/evaluate.sh` (ANSUR II development subset in `../shared`, built-in body model,');
p('seed 1). Raw numbers: `docs/evaluation/*.json`. Nothing here was tuned to these numbers; the rest');
p('of ANSUR II is held back for independent checks.');
p();
const n = Object.fromEntries(sexes.map(s => [s, load(s, 'none').subjects]));
p(`Subjects: ${n.female} women and ${n.male} men. For each subject the avatar is built from the six Virtual`);
p('Caliper inputs (`stature`, `weightkg`, `span`, `crotchheight`, `hipbreadth`, and arm length =');
p('`acromionradialelength + radialestylionlength`), by each regressor, then measured with Caliper\'s own');
p('measurement code and compared with what ANSUR\'s measurers found on the same person.');
p();
// The targets for the default estimator, measured here.
p('## The default estimator at a glance');
p();
p('`auto` against the linear limit from the same six inputs (median and worst over the twelve held-out');
p('columns), the inputs it reproduces (mean absolute difference from the value given, over the five');
p('lengths; weight), the share of people it had to move back inside the population (implausible), and');
p('its error with the paper\'s self-measurement noise against its noise-free error (mean held-out MAE):');
p();
p('| sex | median ratio | worst ratio | lengths reproduced (cm) | weight (kg) | implausible | implausible, self noise | self / noise-free |');
p('|---|---|---|---|---|---|---|---|');
for (const sex of sexes) {
  const a = load(sex, 'none').regressors.auto, s = load(sex, 'self').regressors.auto;
  const lengths = ['stature', 'span', 'crotchheight', 'hipbreadth', 'armlength'].map(k => a.inputs[k].mae_cm);
  const mean = (h) => heldOut.reduce((t, c) => t + h[c].mae_cm, 0) / heldOut.length;
  p(`| ${sex} | ${f(a.ratio_to_linear_median)} | ${f(a.ratio_to_linear_worst.ratio)} (${a.ratio_to_linear_worst.column}) | ` +
    `${f(lengths.reduce((t, x) => t + x, 0) / lengths.length)} (arm length ${f(a.inputs.armlength.mae_cm)}) | ${f(a.inputs.weight.mae_kg)} | ` +
    `${f(a.implausible_share * 100, 1)} % | ${f(s.implausible_share * 100, 1)} % | ${f(mean(s.held_out) / mean(a.held_out))} |`);
}
p();
p('The built-in models keep K = 20 shape directions, chosen by held-out validation (`caliper model choose-k`;');
p('the curve and the rule are in docs/mannequin.md, "How many shape directions"). The paper\'s R2–R6 still');
p('span their 2^10 corners over the first ten.');
p();
p('Every input is reproduced as given except arm length: a person\'s arm length is measured hanging and');
p('the avatar\'s in a T-pose, and the model\'s real → virtual map between them (paper §3.3) has a residual');
p('of about 1.15 cm, so `auto` holds the arm to that precision rather than to 0.1 mm (docs/cli.md); pinned');
p('exactly, it dragged biacromial breadth to 1.25× its linear limit (women). Chest breadth is taken across');
p('the front of the section, between the arms, and a man\'s back may be wider there (docs/mannequin.md, "The');
p('chest"); where ANSUR\'s chest circumference needs more than even that back gives (a few men, counted');
p('there), the chest grows in breadth and depth by one factor.');
p();
for (const sex of sexes) {
  const d = load(sex, 'none');
  p(`## ${sex === 'female' ? 'Women' : 'Men'}`);
  p();
  p('**Table 1 — inputs reproduced** (avatar − input, MAE / max; cm, weight in kg). Inputs are the');
  p('virtual targets: arm length after the model\'s real → virtual map (paper §3.3).');
  p();
  const inputs = ['stature', 'weight', 'span', 'crotchheight', 'hipbreadth', 'armlength'];
  p(`| regressor | ${inputs.join(' | ')} |`);
  p(`|---|${inputs.map(() => '---').join('|')}|`);
  for (const r of R) {
    const ins = d.regressors[r].inputs;
    p(`| ${r} | ${inputs.map(k => ins[k] ? `${f(ins[k].mae_cm ?? ins[k].mae_kg)} / ${f(ins[k].max_cm ?? ins[k].max_kg)}` : '').join(' | ')} |`);
  }
  p();
  p('**Held-out accuracy** (avatar − measured: MAE, bias in parentheses; cm). The last column is the');
  p('linear limit: a least-squares regression of that column straight on the six inputs, 10-fold');
  p('cross-validated over the same people (`caliper eval` computes it; `--train FILE` fits it on another');
  p('file). A body model that goes through a shape space should come close to it.');
  p();
  p(`| measurement | ${R.join(' | ')} | uniform scale | linear limit (6 inputs) |`);
  p(`|---|${R.map(() => '---').join('|')}|---|---|`);
  const rows = [...heldOut, 'span', 'crotchheight', 'hipbreadth', 'armlength', 'weight'];
  for (const c of rows) {
    const cell = (me) => { const s = me.held_out[c]; if (!s) return '*input*'; const u = c === 'weight' ? 'kg' : 'cm';
      return `${f(s[`mae_${u}`])} (${f(s[`bias_${u}`])})`; };
    p(`| ${c} | ${R.map(r => cell(d.regressors[r])).join(' | ')} | ${cell(d.baselines.uniform_scale)} | ${linearOf(d, c) !== undefined ? f(linearOf(d, c)) : ''} |`);
  }
  p();
  p('**Against the linear limit from the same inputs** (each method\'s held-out MAE / the MAE of a linear');
  p('regression from *its own* inputs, over the twelve held-out columns; 1.00 = as good as the limit):');
  p();
  p('| | ' + R.join(' | ') + ' |');
  p(`|---|${R.map(() => '---').join('|')}|`);
  p(`| median ratio | ${R.map(r => f(d.regressors[r].ratio_to_linear_median)).join(' | ')} |`);
  p(`| worst ratio | ${R.map(r => { const w = d.regressors[r].ratio_to_linear_worst; return w ? `${f(w.ratio)} (${w.column})` : '–'; }).join(' | ')} |`);
  p();
  p(`Implausible avatars (rarer than 1 in 1,000 people of the population; for auto also bodies moved back inside it): ${R.map(r => `${r} ${f(d.regressors[r].implausible_share * 100, 1)} %`).join(', ')}.`);
  p();
  fs.writeFileSync(path.join(path.dirname(outMd), 'evaluation', `held-out-${sex}.svg`), barChart(sex, d));
  p(`![Held-out MAE per measurement, ${sex}](evaluation/held-out-${sex}.svg)`);
  p();
}
p('## With measurement noise');
p();
p('The inputs perturbed with zero-mean Gaussian noise whose MAE is the paper\'s Table 2 (self: a person');
p('measuring themselves with the Virtual Caliper; other: a second person measuring them). Weight is not');
p('perturbed (a bathroom scale; the paper gives no error for it). Held-out MAE (cm) and implausible share:');
p();
p(`| sex | noise | ${R.map(r => `${r} chest / waist / hip-circ.`).join(' | ')} | ${R.map(r => `${r} implausible`).join(' | ')} |`);
p(`|---|---|${R.map(() => '---').join('|')}|${R.map(() => '---').join('|')}|`);
for (const sex of sexes) for (const noise of noises) {
  const d = load(sex, noise);
  const c = (r) => ['chestcircumference', 'waistcircumference', 'buttockcircumference'].map(k => f(d.regressors[r].held_out[k].mae_cm, 1)).join(' / ');
  p(`| ${sex} | ${noise} | ${R.map(c).join(' | ')} | ${R.map(r => f(d.regressors[r].implausible_share * 100, 1) + ' %').join(' | ')} |`);
}
p();
p('The default estimator with noise, against itself without (mean held-out MAE over the twelve columns, cm;');
p('it assumes the noise it is given: `--noise self` / `other`):');
p();
p('| sex | none | self | other | self / none | other / none |');
p('|---|---|---|---|---|---|');
for (const sex of sexes) {
  const mean = (noise) => { const h = load(sex, noise).regressors.auto.held_out; return heldOut.reduce((a, c) => a + h[c].mae_cm, 0) / heldOut.length; };
  const [a, b, c] = noises.map(mean);
  p(`| ${sex} | ${f(a)} | ${f(b)} | ${f(c)} | ${f(b / a)} | ${f(c / a)} |`);
}
p();
p('## Synthetic surface study (Table 4 in spirit)');
p();
p('Bodies drawn from the model\'s own population (β ~ N(0, I)), measured virtually, measurements');
p('perturbed with Table 2 noise, rebuilt by each regressor, aligned as in the paper (common floor,');
p('bounding boxes centred) and compared vertex by vertex (same topology: the distance between');
p('corresponding vertices, an upper bound of the surface-to-surface distance). Mean over bodies of the');
p('mean and of the maximum vertex distance, cm.');
p();
p(`| noise | sex | ${R.map(r => `${r} mean / max`).join(' | ')} |`);
p(`|---|---|${R.map(() => '---').join('|')}|`);
for (const noise of ['self', 'other']) {
  const d = load('female', noise);
  if (!d.synthetic) continue;
  for (const sex of sexes) p(`| ${noise} | ${sex} | ${R.map(r => `${f(d.synthetic[sex][r].mean_cm)} / ${f(d.synthetic[sex][r].max_cm)}`).join(' | ')} |`);
}
p();
p('## How this differs from the paper');
p();
p('- **Real people, not scans.** The paper compared avatars with 3D scans of 20 participants (Table 4:');
p('  1.11–1.18 cm mean surface distance for its best regressors). ANSUR II has no scans, only tape and');
p('  caliper measurements of thousands of soldiers, so here avatars are judged on measurements they were');
p('  not given. The surface distance above is against bodies of the model\'s own space, a best case.');
p('- **A different body model.** The paper used SMPL, learned from CAESAR scans. Caliper\'s built-in body');
p('  is procedural, its shape space learned from ANSUR II dimensions (docs/mannequin.md); its shape');
p('  space is only as rich as the dimensions that drive it.');
p('- **Measurement noise is simulated**, from the paper\'s Table 2 MAEs, not measured.');
p('- **Arm length** is measured hanging in ANSUR (acromion–radiale + radiale–stylion) and in a T-pose on');
p('  the avatar; the model carries a linear real → virtual map for it, fitted on the same population,');
p('  as the paper fitted its maps for hip width and arm length (§3.3).');
p('- **Population.** ANSUR II are young U.S. soldiers (mean BMI 25–28); civilians differ.');
p();
fs.writeFileSync(outMd, lines.join('\n'));
