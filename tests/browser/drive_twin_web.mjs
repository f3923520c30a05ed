// Drives Debian's headless Chromium (playwright-core, no browser download) to twin-web's page while the test's
// services run, and reports what a person would see as one line `RESULT {json}`. The gtest that starts this
// script judges the facts; this script fails (exit 1) only when it cannot carry out a step.
//   node drive_twin_web.mjs --url U --out DIR --chromium PATH --done-file F [--group ID]
// Steps: open the page; read the trend's point count twice, 2.5 s apart, while the replay runs; ask a what-if
// question with the form; wait for an alarm row; wait for F (the test writes it once the services have exited);
// let the page catch up with the server's state; screenshot DIR/twin_web.png; read the final page.
import { chromium } from 'playwright-core';
import fs from 'node:fs';
import path from 'node:path';

const args = Object.fromEntries(process.argv.slice(2).reduce((acc, a, i, all) => {
  if (a.startsWith('--')) acc.push([a.slice(2), all[i + 1]]);
  return acc;
}, []));
for (const k of ['url', 'out', 'chromium', 'done-file']) {
  if (!args[k]) { console.error(`drive_twin_web: --${k} is required`); process.exit(2); }
}
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
const result = { console_errors: [], page_errors: [], failed_requests: [], steps: [] };
const step = (s) => { result.steps.push(s); console.log(`drive_twin_web: ${s}`); };

const browser = await chromium.launch({
  executablePath: args.chromium,
  headless: true,
  // root in a container: Chromium's sandbox needs user namespaces it may not have.
  args: ['--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage'],
});
let code = 0;
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 1000 } });
  page.on('console', (m) => { if (m.type() === 'error') result.console_errors.push(m.text()); });
  page.on('pageerror', (e) => result.page_errors.push(String(e)));
  page.on('requestfailed', (r) => {
    // An event stream is cut when the page switches groups or the browser closes; anything else failing is a defect.
    if (new URL(r.url()).pathname !== '/api/events') result.failed_requests.push(`${r.url()}: ${r.failure()?.errorText}`);
  });
  await page.goto(args.url, { waitUntil: 'load' });
  step('page loaded');
  result.chart_library = await page.evaluate(() => typeof window.Chart === 'function');

  const points = () => page.evaluate(() => Number(document.getElementById('trend').dataset.points));
  const lastIndex = () => page.evaluate(() => {
    const s = window.twinView.state();
    return s && s.group && s.group.last ? s.group.last.index : -1;
  });
  await page.waitForFunction(() => Number(document.getElementById('trend').dataset.points) > 0, null, { timeout: 60000 });
  result.points_first = await points();
  result.index_first = await lastIndex();
  await sleep(2500);
  result.points_second = await points();
  result.index_second = await lastIndex();
  result.selected_group = await page.evaluate(() => window.twinView.selected());
  step(`trend points ${result.points_first} -> ${result.points_second}`);

  // A what-if question through the form: a sustained -10 % on channel 2. The model may not be ready in the
  // first seconds (calibration): a refusal or no reply is asked again, five times at most.
  await page.selectOption('#whatif-channel', '2');
  await page.fill('#whatif-percent', '-10');
  result.whatif_history = [];
  for (let attempt = 1; attempt <= 5; ++attempt) {
    await page.click('#whatif-ask');
    await page.waitForFunction(() => !['asking', 'idle'].includes(document.getElementById('whatif-result').dataset.status),
      null, { timeout: 20000 });
    result.whatif_status = await page.evaluate(() => document.getElementById('whatif-result').dataset.status);
    result.whatif_text = await page.evaluate(() => document.getElementById('whatif-result').innerText);
    result.whatif_rows = await page.evaluate(() => document.querySelectorAll('#whatif-result table tr').length);
    result.whatif_attempts = attempt;
    result.whatif_history.push(`${result.whatif_status}: ${result.whatif_text.split('\n')[0]}`);
    if (result.whatif_status === 'answered') break;
    await sleep(2000);
  }
  step(`what-if: ${result.whatif_status} after ${result.whatif_attempts} attempt(s)`);

  await page.waitForSelector('#alarms tbody tr[data-alarm-id]', { timeout: 90000 });
  result.first_alarm_row = await page.evaluate(() => document.querySelector('#alarms tbody tr[data-alarm-id]').innerText);
  result.first_alarm_id = await page.evaluate(() => document.querySelector('#alarms tbody tr[data-alarm-id]').dataset.alarmId);
  result.first_alarm_at_index = await lastIndex();
  step(`alarm on the page: ${result.first_alarm_id} (page at snapshot ${result.first_alarm_at_index})`);

  const doneDeadline = Date.now() + 150000;
  while (!fs.existsSync(args['done-file'])) {
    if (Date.now() > doneDeadline) throw new Error('the test never said the services were done');
    await sleep(200);
  }
  // The page has caught up when it shows the version the server serves now (nothing changes any more).
  await page.waitForFunction(async () => {
    const group = encodeURIComponent(window.twinView.selected());
    const s = await (await fetch(`/api/state?group=${group}`, { cache: 'no-store' })).json();
    const shown = window.twinView.state();
    return shown && shown.version === s.version;
  }, null, { timeout: 20000, polling: 250 });
  step('page caught up with the final state');
  fs.mkdirSync(args.out, { recursive: true });
  result.screenshot = path.join(args.out, 'twin_web.png');
  await page.screenshot({ path: result.screenshot, fullPage: true });
  result.points_final = await points();
  result.index_final = await lastIndex();
  result.open_alarm_ids = await page.evaluate(() =>
    [...document.querySelectorAll('#alarms tbody tr[data-alarm-id]')].map((tr) => tr.dataset.alarmId).sort());
  result.recommendation_items = await page.evaluate(() => document.querySelectorAll('#recs li[data-recommendation-id]').length);
  result.graph_edges = await page.evaluate(() => document.querySelectorAll('#graph path.edge').length);
  result.graph_info = await page.evaluate(() => document.getElementById('graph-info').textContent);
  result.page_version = await page.evaluate(() => window.twinView.state().version);
  result.connection = await page.evaluate(() => document.getElementById('conn').textContent);
  step('final page read');
} catch (e) {
  result.error = String(e && e.stack ? e.stack : e);
  code = 1;
} finally {
  await browser.close();
}
console.log(`RESULT ${JSON.stringify(result)}`);
process.exit(code);
