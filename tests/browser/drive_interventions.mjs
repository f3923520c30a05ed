// Drives Debian's headless Chromium (playwright-core) to twin-web's page after a closed-loop run and reads the
// Interventions card as an operator sees it: for the approved group (--group) every row's request id, status and
// cell texts and the count badge; for the unapproved group (--other) the number of intervention rows. Reports
// `RESULT {json}`; the gtest judges the facts, this script fails (exit 1) only when it cannot carry out a step.
//   node drive_interventions.mjs --url U --out DIR --chromium PATH --group G --other G2 [--user NAME --password P]
// (--user and --password: twin-web's basic authentication.)
// Screenshots: DIR/twin_web_interventions.png (the whole page), DIR/twin_web_interventions_card.png (the card).
import { chromium } from 'playwright-core';
import fs from 'node:fs';
import path from 'node:path';

const args = Object.fromEntries(process.argv.slice(2).reduce((acc, a, i, all) => {
  if (a.startsWith('--')) acc.push([a.slice(2), all[i + 1]]);
  return acc;
}, []));
for (const k of ['url', 'out', 'chromium', 'group', 'other']) {
  if (!args[k]) { console.error(`drive_interventions: --${k} is required`); process.exit(2); }
}

const result = { console_errors: [], page_errors: [], failed_requests: [], steps: [] };
const step = (s) => { result.steps.push(s); console.log(`drive_interventions: ${s}`); };
const card = () => {
  const cells = ['approved', 'lever', 'window', 'target', 'predicted', 'observed', 'result', 'trust'];
  const rows = [...document.querySelectorAll('#interventions tbody tr[data-request-id]')].map((tr) => {
    const r = { request_id: tr.dataset.requestId, status: tr.dataset.status,
      approved_title: tr.querySelector('.approved').title };
    for (const c of cells) r[c] = tr.querySelector(`.${c}`).textContent;
    return r;
  });
  return { rows, count: document.getElementById('intervention-count').textContent,
    body_text: document.querySelector('#interventions tbody').textContent };
};

const browser = await chromium.launch({
  executablePath: args.chromium,
  headless: true,
  args: ['--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage'],  // root in a container: no user namespaces
});
let code = 0;
try {
  const credentials = args.user ? { httpCredentials: { username: args.user, password: args.password } } : {};
  const page = await browser.newPage({ viewport: { width: 1280, height: 1000 }, ...credentials });
  page.on('console', (m) => { if (m.type() === 'error') result.console_errors.push(m.text()); });
  page.on('pageerror', (e) => result.page_errors.push(String(e)));
  page.on('requestfailed', (r) => {
    if (new URL(r.url()).pathname !== '/api/events') result.failed_requests.push(`${r.url()}: ${r.failure()?.errorText}`);
  });
  const open = async (group, selector) => {
    await page.goto(`${args.url}?group=${encodeURIComponent(group)}`, { waitUntil: 'load' });
    await page.waitForSelector(selector, { timeout: 30000 });
    return page.evaluate(card);
  };
  result.group = await open(args.group, '#interventions tbody tr[data-request-id]');
  step(`${args.group}: ${result.group.rows.length} row(s), count ${result.group.count}`);
  fs.mkdirSync(args.out, { recursive: true });
  result.screenshot = path.join(args.out, 'twin_web_interventions.png');
  await page.screenshot({ path: result.screenshot, fullPage: true });
  result.screenshot_card = path.join(args.out, 'twin_web_interventions_card.png');
  await page.locator('#intervention-card').screenshot({ path: result.screenshot_card });
  result.page_overflow_x = await page.evaluate(() =>
    document.documentElement.scrollWidth - document.documentElement.clientWidth);
  // The other group's card once it has been rendered for that group (its placeholder row).
  result.other = await open(args.other, '#interventions tbody tr td.muted');
  step(`${args.other}: ${result.other.rows.length} row(s): ${result.other.body_text}`);
} catch (e) {
  result.error = String(e && e.stack ? e.stack : e);
  code = 1;
} finally {
  await browser.close();
}
console.log(`RESULT ${JSON.stringify(result)}`);
process.exit(code);
