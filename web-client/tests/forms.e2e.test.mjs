// End-to-end test of the algorithm panel's menu and forms, against the real
// server and Debian's chromium:
//   CGVIEW_SERVER=build/bin/cgview-server CGVIEW_SAMPLES=build/samples node --test tests/forms.e2e.test.mjs
//
// Controls are found as a user finds them, by their visible labels and
// roles. The menu is grouped by area and narrowed by a search box. A form
// lists its fields in the algorithm's declared order (x-cgview-order), folds
// the advanced ones under "Advanced", shows a field with x-cgview-when only
// while the parameter it names has one of its values (and leaves it out of
// the job), and "Reset to defaults" puts every control back. Its choices are
// read whole, within the sidebar. Once voxelize's grid is chosen with "Run on
// this", the menu offers only the algorithms that run on a voxel grid, and
// says so when none does.
//
// Environment: CGVIEW_SERVER, CHROMIUM.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import path from 'node:path';
import { repo, useViewer } from './harness.mjs';

const elephant = path.join(repo, 'build', 'samples', 'elephant.off');
const v = useViewer({ tmpPrefix: 'cgview-e2e-forms-', mesh: elephant });

/** GET /api/v1/algorithms, as the page reads it. */
let algorithms = [];
const algorithm = (name) => {
  const a = algorithms.find((x) => x.name === name);
  assert.ok(a, `the server lists ${name}`);
  return a;
};
const firstKind = (a) => a.inputs?.[0]?.kind ?? 'mesh';
/** The areas in the menu's order: alphabetical, examples last. */
const areaOrder = (list) => {
  const last = ['examples', 'other'];
  return [...new Set(list.map((a) => a.area || 'other'))].sort((x, y) => last.indexOf(x) - last.indexOf(y) || x.localeCompare(y));
};

const menu = () => v.page.getByRole('combobox', { name: 'Algorithm', exact: true });
const search = () => v.page.getByRole('searchbox', { name: 'Search algorithms' });
const form = () => v.page.locator('form.algorithm-form');
/** A field of the form by its visible label. */
const field = (label) => form().getByLabel(label, { exact: true });
const title = (name, param) => algorithm(name).params.properties[param].title;

async function choose(name) {
  await menu().selectOption(name);
  await v.page.locator(`form.algorithm-form[data-algorithm="${name}"]`).waitFor();
}

/** The options of the menu: value, text and the label of their group. */
const menuOptions = () =>
  menu()
    .locator('option')
    .evaluateAll((os) => os.map((o) => ({ name: o.value, text: o.textContent, group: o.parentElement.tagName === 'OPTGROUP' ? o.parentElement.label : null })));

const sameSet = (a, b, what) => assert.deepEqual([...a].sort(), [...b].sort(), what);

async function waitDone(name) {
  const li = v.page.locator(`#jobs li.job[data-algorithm="${name}"][data-state="done"]`).first();
  await li.waitFor({ timeout: 120000 }).catch(async (e) => {
    const states = await v.page.locator('#jobs li.job').evaluateAll((ls) => ls.map((l) => `${l.dataset.algorithm}:${l.dataset.state}`));
    throw new Error(`${name} never showed done: ${e.message}\njobs: ${states.join(' ')}${v.describeProblems()}\n${v.server.log()}`);
  });
  return li;
}

test('the server describes its forms: the declared order, the advanced parameters and the conditions', async () => {
  const r = await fetch(`${v.server.url}/api/v1/algorithms`);
  assert.equal(r.status, 200);
  algorithms = (await r.json()).algorithms;
  assert.ok(algorithms.length > 20, `the algorithms: ${algorithms.map((a) => a.name)}`);
  const chaos = algorithm('chaos_map').params;
  assert.ok(
    Array.isArray(chaos['x-cgview-order']),
    `chaos_map's params have no x-cgview-order: build/bin/cgview-server predates the form fields (rebuild it)\n${JSON.stringify(chaos)}`,
  );
  sameSet(chaos['x-cgview-order'], Object.keys(chaos.properties), 'x-cgview-order names every parameter once');
  assert.deepEqual(chaos.properties.u['x-cgview-when'], { param: 'map', in: ['ikeda', 'composite'] });
  assert.deepEqual(chaos.properties.r['x-cgview-when'], { param: 'map', in: ['logistic'] });
  assert.equal(algorithm('skeleton_projection').params.properties.contexts['x-cgview-advanced'], true);
  assert.deepEqual(algorithm('skeleton_mcf').params.properties.medially_centered_speed_tradeoff['x-cgview-when'], { param: 'medially_centered', in: ['true'] });
});

test('the menu is grouped by area, each algorithm under its own', async () => {
  await menu().waitFor();
  const options = await menuOptions();
  sameSet(
    options.map((o) => o.name),
    algorithms.map((a) => a.name),
    'the menu lists every algorithm once',
  );
  for (const o of options) assert.equal(o.group, algorithm(o.name).area || 'other', `${o.name} is under its area`);
  const groups = await menu()
    .locator('optgroup')
    .evaluateAll((gs) => gs.map((g) => g.label));
  assert.deepEqual(groups, areaOrder(algorithms), 'one group per area');
  for (const area of ['chaos', 'filters', 'sdf', 'skeleton', 'voxel', 'examples']) assert.ok(groups.includes(area), `a group ${area}: ${groups}`);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('the search box narrows the menu by name, title and description as the user types', async () => {
  await search().pressSequentially('voxel');
  let options = await menuOptions();
  const voxel = algorithms.filter((a) => a.area === 'voxel').map((a) => a.name);
  sameSet(
    options.map((o) => o.name),
    voxel,
    'only the voxel algorithms are left',
  );
  assert.ok(options.every((o) => o.group === 'voxel'));
  assert.ok(voxel.includes(await form().getAttribute('data-algorithm')), 'the form is of one of them');

  // A word that only some descriptions hold finds those algorithms.
  const named = (a) => `${a.name} ${a.name.replace(/_/g, ' ')} ${a.title} ${a.area}`.toLowerCase();
  const words = new Set(algorithms.flatMap((a) => a.description.toLowerCase().match(/[a-z]{7,}/g) ?? []));
  const word = [...words].find((w) => !algorithms.some((a) => named(a).includes(w)));
  assert.ok(word, 'a word of the descriptions that no name or title holds');
  await search().fill(word);
  options = await menuOptions();
  sameSet(
    options.map((o) => o.name),
    algorithms.filter((a) => a.description.toLowerCase().includes(word)).map((a) => a.name),
    `the search for "${word}" finds the algorithms whose description holds it`,
  );

  // Nothing found: the panel says so in place of an empty menu.
  await search().fill('no such algorithm at all');
  const none = v.page.locator('#algorithms').getByRole('status');
  assert.match(await none.innerText(), /No algorithm matches/);
  assert.equal(await menu().isVisible(), false, 'no empty menu');
  assert.equal(await form().count(), 0, 'no form');

  await search().fill('');
  assert.equal((await menuOptions()).length, algorithms.length, 'cleared, the menu lists them all');
  assert.equal(await none.isVisible(), false);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test("chaos_map's fields follow its declared order", async () => {
  await choose('chaos_map');
  const order = algorithm('chaos_map').params['x-cgview-order'];
  const rows = await form()
    .locator('[data-param-row]')
    .evaluateAll((rs) => rs.map((r) => r.dataset.paramRow));
  assert.deepEqual(rows, order, 'the rows in x-cgview-order, not sorted by name');
  // What the user reads, top to bottom: the labels of the fields shown.
  const labels = await form()
    .locator('.param-label')
    .evaluateAll((ls) => ls.filter((l) => l.offsetParent !== null).map((l) => [l.textContent, l.getBoundingClientRect().top]));
  const tops = labels.map(([, top]) => top);
  assert.deepEqual(
    tops,
    [...tops].sort((a, b) => a - b),
    'shown top to bottom in that order',
  );
  const shown = labels.map(([text]) => text);
  const expected = order.map((n) => title('chaos_map', n)).filter((t) => shown.includes(t));
  assert.deepEqual(shown, expected);
  assert.equal(shown[0], title('chaos_map', order[0]), 'the most used first');
});

test('map = logistic shows "Logistic r" and hides "Ikeda u"; the job sent has no u', async () => {
  await choose('chaos_map');
  const map = field(title('chaos_map', 'map'));
  assert.equal(await map.locator('option:checked').innerText(), 'ikeda', 'the default map');
  assert.equal(await field('Ikeda u').isVisible(), true, 'u for ikeda');
  assert.equal(await field('Logistic r').isVisible(), false, 'no r for ikeda');

  await map.selectOption({ label: 'logistic' });
  assert.equal(await field('Logistic r').isVisible(), true, 'r for logistic');
  for (const label of ['Ikeda u', 'Henon a', 'Henon b', 'Cat grid N']) assert.equal(await field(label).isVisible(), false, `no ${label} for logistic`);

  await field('Logistic r').fill('3.9');
  const sent = v.page.waitForRequest((r) => r.method() === 'POST' && new URL(r.url()).pathname === '/api/v1/jobs');
  await form().getByRole('button', { name: 'Run', exact: true }).click();
  const request = await sent;
  const body = request.postDataJSON();
  assert.equal(body.algorithm, 'chaos_map');
  assert.equal(body.params.map, 'logistic');
  assert.equal(body.params.r, 3.9);
  for (const p of ['u', 'a', 'b', 'grid']) assert.ok(!(p in body.params), `no ${p} sent: ${JSON.stringify(body.params)}`);
  assert.equal((await request.response()).status(), 201);
  await waitDone('chaos_map');
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test("every parameter with a condition is shown exactly for its parameter's values", async () => {
  let checked = 0;
  for (const a of algorithms) {
    const properties = a.params.properties ?? {};
    const dependent = Object.entries(properties).filter(([, s]) => s['x-cgview-when']);
    if (!dependent.length) continue;
    await choose(a.name);
    const fold = form().locator('details.advanced');
    if (await fold.count()) await fold.evaluate((d) => (d.open = true));
    for (const param of new Set(dependent.map(([, s]) => s['x-cgview-when'].param))) {
      const on = properties[param];
      const control = field(on.title);
      const values = on.type === 'boolean' ? ['true', 'false'] : on.enum.map(String);
      for (const value of values) {
        if (on.type === 'boolean') await control.setChecked(value === 'true');
        else await control.selectOption({ label: value });
        for (const [name, s] of dependent.filter(([, s]) => s['x-cgview-when'].param === param)) {
          const expected = s['x-cgview-when'].in.includes(value);
          assert.equal(await field(s.title).isVisible(), expected, `${a.name}: "${s.title}" (${name}) with ${param} = ${value}`);
          ++checked;
        }
      }
    }
  }
  assert.ok(checked >= 10, `conditions checked: ${checked}`);

  // The examples of the issue, by their labels.
  await choose('components');
  await field(title('components', 'mode')).selectOption({ label: 'drop_smaller_than' });
  assert.equal(await field(title('components', 'min_faces')).isVisible(), true);
  await field(title('components', 'mode')).selectOption({ label: 'keep_largest' });
  assert.equal(await field(title('components', 'min_faces')).isVisible(), false);
  await choose('smooth');
  assert.equal(await field(title('smooth', 'time')).isVisible(), true, 'the time step for mean_curvature_flow, the default');
  await field(title('smooth', 'method')).selectOption({ label: 'angle_and_area' });
  assert.equal(await field(title('smooth', 'time')).isVisible(), false);
  await choose('skeleton_mcf');
  await form().locator('details.advanced summary').click();
  const tradeoff = field(title('skeleton_mcf', 'medially_centered_speed_tradeoff'));
  assert.equal(await tradeoff.isVisible(), true, 'medially centred by default');
  await field(title('skeleton_mcf', 'medially_centered')).uncheck();
  assert.equal(await tradeoff.isVisible(), false);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('the Advanced fold hides "Render contexts" of skeleton_projection until opened', async () => {
  await choose('skeleton_projection');
  const fold = form().locator('details.advanced');
  assert.equal(await fold.getAttribute('open'), null, 'closed at first');
  const contexts = field('Render contexts');
  assert.equal(await contexts.count(), 1);
  assert.equal(await contexts.isVisible(), false, 'folded');
  const summary = fold.locator('summary');
  assert.equal(await summary.innerText(), 'Advanced');
  // The fold comes below the other fields.
  const properties = algorithm('skeleton_projection').params.properties;
  for (const [name, s] of Object.entries(properties)) {
    const inFold = (await fold.locator(`[data-param-row="${name}"]`).count()) === 1;
    assert.equal(inFold, s['x-cgview-advanced'] === true, `${name} ${inFold ? 'is' : 'is not'} under Advanced`);
    if (!inFold) assert.equal(await field(s.title).isVisible(), true, `${s.title} shown`);
  }
  await summary.click();
  assert.equal(await contexts.isVisible(), true, 'shown once opened');
  assert.equal(Number(await contexts.inputValue()), properties.contexts.default);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('"Reset to defaults" puts every control back to its default', async () => {
  await choose('chaos_map');
  const chaos = algorithm('chaos_map').params.properties;
  const steps = field(chaos.steps.title);
  await field(chaos.map.title).selectOption({ label: 'henon' });
  await field('Henon a').fill('1.2');
  await steps.fill(String(chaos.steps.default + 3));
  assert.equal(await field('Ikeda u').isVisible(), false);
  await form().getByRole('button', { name: 'Reset to defaults' }).click();
  assert.equal(await field(chaos.map.title).locator('option:checked').innerText(), chaos.map.default);
  assert.equal(Number(await steps.inputValue()), chaos.steps.default);
  assert.equal(Number(await field('Henon a').inputValue()), chaos.a.default);
  assert.equal(await field('Ikeda u').isVisible(), true, 'the fields of the default map are back');
  assert.equal(await field('Henon a').isVisible(), false);

  await choose('skeleton_mcf');
  const mcf = algorithm('skeleton_mcf').params.properties;
  await field(mcf.medially_centered.title).uncheck();
  await field(mcf.max_iterations.title).fill('7');
  await form().getByRole('button', { name: 'Reset to defaults' }).click();
  assert.equal(await field(mcf.medially_centered.title).isChecked(), mcf.medially_centered.default);
  assert.equal(Number(await field(mcf.max_iterations.title).inputValue()), mcf.max_iterations.default);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

// Whether a select shows its choice whole, within the panel: measured in the
// page. A native select clips its text without overflowing, so there the
// widest option is measured with the select's font against its inside.
const selectFit = (select) =>
  select.evaluate((s) => {
    const panel = document.getElementById('algorithms').getBoundingClientRect();
    const box = s.getBoundingClientRect();
    const style = getComputedStyle(s);
    const ctx = document.createElement('canvas').getContext('2d');
    ctx.font = `${style.fontWeight} ${style.fontSize} ${style.fontFamily}`;
    const widest = Math.max(...[...s.options].map((o) => ctx.measureText(o.textContent).width));
    const native = style.appearance !== 'base-select';
    return {
      name: s.dataset.param ?? s.id,
      right: box.right,
      panelRight: panel.right,
      scrollWidth: s.scrollWidth,
      clientWidth: s.clientWidth,
      scrollHeight: s.scrollHeight,
      clientHeight: s.clientHeight,
      // The arrow and the paddings take about 24 px of a native select.
      textFits: native ? widest + 24 <= s.clientWidth : true,
    };
  });

function assertFits(m, what) {
  const text = `${what}: ${JSON.stringify(m)}`;
  assert.ok(m.right <= m.panelRight + 0.5, `within the panel: ${text}`);
  assert.ok(m.scrollWidth <= m.clientWidth, `not cut off across: ${text}`);
  assert.ok(m.scrollHeight <= m.clientHeight + 1, `not cut off down: ${text}`);
  assert.ok(m.textFits, `its widest choice is read whole: ${text}`);
}

test('choices are never cut off: every select and form fits the sidebar', async () => {
  // The menu, on the algorithm of the longest title.
  const longest = [...algorithms].sort((a, b) => b.title.length - a.title.length)[0];
  await choose(longest.name);
  assertFits(await selectFit(menu()), `the menu on "${longest.title}"`);
  let measured = 0;
  for (const a of algorithms) {
    if (!Object.values(a.params.properties ?? {}).some((s) => Array.isArray(s.enum))) continue;
    await choose(a.name);
    const fold = form().locator('details.advanced');
    if (await fold.count()) await fold.evaluate((d) => (d.open = true));
    for (const select of await form().locator('select').all()) {
      if (!(await select.isVisible())) continue;
      // Each choice chosen in turn: the select shows the chosen one.
      for (const label of await select.locator('option').allInnerTexts()) {
        await select.selectOption({ label });
        assertFits(await selectFit(select), `${a.name}'s select = ${label}`);
        ++measured;
      }
    }
    const overflow = await form().evaluate((f) => {
      const sidebar = f.closest('.sidebar');
      return { form: [f.scrollWidth, f.clientWidth], sidebar: [sidebar.scrollWidth, sidebar.clientWidth] };
    });
    assert.ok(overflow.form[0] <= overflow.form[1] && overflow.sidebar[0] <= overflow.sidebar[1], `${a.name}'s form fits the sidebar: ${JSON.stringify(overflow)}`);
  }
  assert.ok(measured >= 20, `choices measured: ${measured}`);
  assert.deepEqual(v.problems, [], v.describeProblems());
});

test('"Run on this" on a voxel grid offers only the algorithms that run on one', async () => {
  await choose('voxelize');
  await form().locator('input[data-param="resolution"]').fill('16');
  await form().getByRole('button', { name: 'Run', exact: true }).click();
  const vox = await waitDone('voxelize');
  const gridAlgorithms = algorithms.filter((a) => firstKind(a) === 'voxel_grid').map((a) => a.name);
  assert.ok(gridAlgorithms.length >= 1, 'the server has an algorithm on voxel grids');

  await vox.locator('.artifact-voxel_grid[data-artifact="grid"]').getByRole('button', { name: 'Run on this' }).click();
  await v.page.waitForFunction((n) => document.querySelectorAll('#algorithm-menu option').length === n, gridAlgorithms.length, { timeout: 10000 });
  const options = await menuOptions();
  sameSet(
    options.map((o) => o.name),
    gridAlgorithms,
    'only the algorithms whose first input is a voxel grid',
  );
  const chosen = await form().getAttribute('data-algorithm');
  assert.ok(gridAlgorithms.includes(chosen), `the form is of one of them: ${chosen}`);
  assert.match(await form().locator('.run-target').innerText(), /voxelize/, 'the form runs on the grid');
  // The search narrows these, not all of them.
  await search().fill('sdf');
  assert.match(await v.page.locator('#algorithms').getByRole('status').innerText(), /No algorithm matches/);
  await search().fill('');
  assert.equal((await menuOptions()).length, gridAlgorithms.length);

  // On a server where nothing runs on a voxel grid, the panel says so.
  const other = await v.browser.newPage({ viewport: { width: 1280, height: 800 } });
  try {
    await other.route('**/api/v1/algorithms', async (route) => {
      const response = await route.fetch();
      const body = await response.json();
      body.algorithms = body.algorithms.filter((a) => firstKind(a) !== 'voxel_grid');
      await route.fulfill({ response, json: body });
    });
    await other.goto(v.server.url + '/');
    await other.waitForFunction(() => window.__cgview?.ready === true, null, { timeout: 30000 });
    const job = await vox.getAttribute('data-job-id');
    await other.locator(`#jobs li.job[data-job-id="${job}"] .artifact-voxel_grid[data-artifact="grid"]`).getByRole('button', { name: 'Run on this' }).click();
    const none = other.locator('#algorithms').getByRole('status');
    await none.waitFor({ timeout: 10000 });
    assert.match(await none.innerText(), /No algorithm runs on a voxel grid/);
    assert.equal(await other.locator('#algorithm-menu').isVisible(), false, 'no empty menu');
    assert.equal(await other.locator('form.algorithm-form').count(), 0, 'no form');
  } finally {
    await other.close();
  }

  // Run, the grid is used: the menu offers every algorithm again.
  await choose('grid_surface');
  await form().getByRole('button', { name: 'Run', exact: true }).click();
  await waitDone('grid_surface');
  await v.page.waitForFunction((n) => document.querySelectorAll('#algorithm-menu option').length === n, algorithms.length, { timeout: 10000 });
  assert.deepEqual(v.problems, [], v.describeProblems());
});
