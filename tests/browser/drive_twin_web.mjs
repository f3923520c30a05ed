// Drives Debian's headless Chromium (playwright-core, no browser download) to twin-web's page while the test's
// services run, and reports what a person would see as one line `RESULT {json}`. The gtest that starts this
// script judges the facts; this script fails (exit 1) only when it cannot carry out a step.
//   node drive_twin_web.mjs --url U --out DIR --chromium PATH --done-file F [--group ID]
// Steps: open the page; read the trend's point count twice, 2.5 s apart, while the replay runs; ask a what-if
// question with the form; wait for an alarm row; wait for F (the test writes it once the services have exited);
// let the page catch up with the server's state; screenshot DIR/twin_web.png; read the final page (the operator's
// facts: status lines, root-cause node, UTC axes and times, time scales, reasons without horizontal overflow);
// then open the group's link (?group=ID) in a second page whose event stream never answers, screenshot it at
// load (DIR/twin_web_at_load.png, 1280x900) and read it: the first response alone must draw the whole state.
import fs from 'node:fs';
import path from 'node:path';
import { drive, pageOverflowX, parseArgs } from './drive_common.mjs';

const args = parseArgs('drive_twin_web', ['url', 'out', 'chromium', 'done-file']);
// What the operator reads, from the page's DOM and its chart (runs in the page).
function readOperatorFacts() {
  const text = (el) => (el ? el.textContent.trim() : null);
  const chart = window.Chart && window.Chart.getChart ? window.Chart.getChart(document.getElementById('trend')) : null;
  const x = chart ? chart.scales.x : null;
  const shown = window.twinView.state();
  const reasons = new Map(((shown && shown.group && shown.group.alarms) || []).map((a) => [a.id, a.reason]));
  return {
    initial: document.documentElement.dataset.initial || '',
    status_rows: [...document.querySelectorAll('#group-status tbody tr[data-group]')].map((tr) => ({
      group: tr.dataset.group, state: text(tr.querySelector('.state')), worst: text(tr.children[2]),
      root: text(tr.querySelector('.root')), action: text(tr.querySelector('.action')),
      prognosis: text(tr.querySelector('.prognosis')), learning: text(tr.querySelector('.learning')),
      time: text(tr.querySelector('.time')), active: tr.classList.contains('active') })),
    group_links: [...document.querySelectorAll('#group-status a.group-link')].map((a) => a.getAttribute('href')),
    root_nodes: [...document.querySelectorAll('#graph circle.root-cause')].map((c) => Number(c.dataset.channel)),
    root_labels: document.querySelectorAll('#graph .root-cause-label').length,
    page_root_channel: window.twinView.rootChannel(),
    x_title: x ? x.options.title.text : null,
    x_ticks: x ? x.ticks.map((t) => String(t.label)) : [],
    alarm_header: [...document.querySelectorAll('#alarms thead th')].map((th) => th.textContent),
    alarm_rows: [...document.querySelectorAll('#alarms tbody tr[data-alarm-id]')].map((tr) => ({
      id: tr.dataset.alarmId, scale: text(tr.querySelector('td.scale')), since: text(tr.querySelector('td.since')),
      next: text(tr.querySelector('td.next')), reason_shown: text(tr.querySelector('.reason-text')),
      reason_served: reasons.get(tr.dataset.alarmId) || null,
      reason_overflow: tr.querySelector('td.reason').scrollWidth - tr.querySelector('td.reason').clientWidth,
      action: text(tr.querySelector('td.reason .action')) })),
    alarm_sections: [...document.querySelectorAll('#alarms tbody tr.section')].map((tr) => tr.textContent),
    prognosis_rows: [...document.querySelectorAll('#prognosis tbody tr[data-level]')].map((tr) => tr.innerText),
    page_overflow_x: document.documentElement.scrollWidth - document.documentElement.clientWidth,
    alarms_overflow_x: document.getElementById('alarms').scrollWidth - document.getElementById('alarms').parentElement.clientWidth,
    stamp: text(document.getElementById('stamp')),
    graph_info: text(document.getElementById('graph-info')),
    trend_info: text(document.getElementById('trend-info')),
    empty_hidden: document.getElementById('empty').hidden,
    empty_visible: document.getElementById('empty').offsetParent !== null,
  };
}

const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

await drive('drive_twin_web', args.chromium, async ({ browser, page, result, step }) => {
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
  result.operator = await page.evaluate(readOperatorFacts);
  // The causal graph and the prognosis side by side (the full page is long: every reason is shown whole).
  const band = await page.evaluate(() => {  // page coordinates of the row that holds both cards
    const r = ['#graph', '#prognosis'].map((s) => document.querySelector(s).closest('section').getBoundingClientRect());
    return { top: Math.min(...r.map((b) => b.top)) + window.scrollY - 8, bottom: Math.max(...r.map((b) => b.bottom)) + window.scrollY + 8 };
  });
  const top = band.top, bottom = band.bottom;
  result.screenshot_graph = path.join(args.out, 'twin_web_graph.png');
  await page.screenshot({ path: result.screenshot_graph, fullPage: true, clip: { x: 0, y: top, width: 1280, height: bottom - top } });
  step('final page read');

  // The link of the group, in a page whose event stream hangs: whatever it shows came with the first response.
  const link = result.operator.group_links[0] || '';
  const cold = await browser.newPage({ viewport: { width: 1280, height: 900 } });
  cold.on('console', (m) => { if (m.type() === 'error') result.console_errors.push(`at load: ${m.text()}`); });
  cold.on('pageerror', (e) => result.page_errors.push(`at load: ${e}`));
  await cold.route('**/api/events**', () => {});  // never fulfilled: no event reaches this page
  await cold.goto(new URL(link, args.url).toString(), { waitUntil: 'load' });
  result.screenshot_at_load = path.join(args.out, 'twin_web_at_load.png');
  await cold.screenshot({ path: result.screenshot_at_load });
  result.at_load = await cold.evaluate(readOperatorFacts);
  result.at_load.url = cold.url();
  result.at_load.connection = await cold.evaluate(() => document.getElementById('conn').textContent);
  result.at_load.points = await cold.evaluate(() => Number(document.getElementById('trend').dataset.points));
  result.at_load.selected = await cold.evaluate(() => window.twinView.selected());
  await cold.unroute('**/api/events**');
  await cold.close();
  step(`at load (${link}): ${result.at_load.points} points, ${result.at_load.alarm_rows.length} alarm rows`);
});
