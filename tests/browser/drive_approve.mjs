// Drives Debian's headless Chromium (playwright-core) to twin-web's page while the closed loop runs and approves a
// recommended lever as an operator does: signs in (basic authentication), types another name into the alarm
// form's user field (the authenticated user must win), waits for the approve button under the group's lever
// recommendation, clicks it, accepts the confirmation and waits for the page's answer. Reports `RESULT {json}`
// (the button's text, the confirmation's text, the answer's status, request id and text); the gtest judges the
// facts, this script fails (exit 1) only when it cannot carry out a step.
//   node drive_approve.mjs --url U --out DIR --chromium PATH --group G --user NAME --password P --typed-user NAME
// Screenshot: DIR/twin_web_approve.png (the recommendations card after the answer).
import { chromium } from 'playwright-core';
import fs from 'node:fs';
import path from 'node:path';

const args = Object.fromEntries(process.argv.slice(2).reduce((acc, a, i, all) => {
  if (a.startsWith('--')) acc.push([a.slice(2), all[i + 1]]);
  return acc;
}, []));
for (const k of ['url', 'out', 'chromium', 'group', 'user', 'password', 'typed-user']) {
  if (!args[k]) { console.error(`drive_approve: --${k} is required`); process.exit(2); }
}

const result = { console_errors: [], page_errors: [], failed_requests: [], steps: [], dialogs: [] };
const step = (s) => { result.steps.push(s); console.log(`drive_approve: ${s}`); };

const browser = await chromium.launch({
  executablePath: args.chromium,
  headless: true,
  args: ['--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage'],  // root in a container: no user namespaces
});
let code = 0;
try {
  const context = await browser.newContext({ viewport: { width: 1280, height: 1000 },
    httpCredentials: { username: args.user, password: args.password } });
  const page = await context.newPage();
  page.on('console', (m) => { if (m.type() === 'error') result.console_errors.push(m.text()); });
  page.on('pageerror', (e) => result.page_errors.push(String(e)));
  page.on('requestfailed', (r) => {
    if (new URL(r.url()).pathname !== '/api/events') result.failed_requests.push(`${r.url()}: ${r.failure()?.errorText}`);
  });
  page.on('dialog', async (d) => { result.dialogs.push({ type: d.type(), message: d.message() }); await d.accept(); });
  await page.goto(`${args.url}?group=${encodeURIComponent(args.group)}`, { waitUntil: 'load' });
  await page.fill('#aa-user', args['typed-user']);
  const button = page.locator('#recs button.approve').first();
  await button.waitFor({ state: 'visible', timeout: 60000 });
  result.button_text = await button.textContent();
  result.recommendation_id = await button.getAttribute('data-recommendation-id');
  step(`button "${result.button_text}" for ${result.recommendation_id}`);
  await button.click();
  await page.waitForSelector('#approve-result:is([data-status=published],[data-status=refused],[data-status=error])',
    { timeout: 20000 });
  result.answer = await page.evaluate(() => {
    const out = document.getElementById('approve-result');
    return { status: out.dataset.status, request_id: out.dataset.requestId, text: out.textContent };
  });
  step(`answer ${result.answer.status}: ${result.answer.text}`);
  // The page shows who approved it under the recommendation once the approval comes back from the bus.
  await page.waitForSelector(`#recs .approval[data-approved=true]`, { timeout: 10000 });
  result.approved_note = await page.locator('#recs .approval[data-approved=true]').first().textContent();
  fs.mkdirSync(args.out, { recursive: true });
  result.screenshot = path.join(args.out, 'twin_web_approve.png');
  await page.locator('#recs').locator('xpath=..').screenshot({ path: result.screenshot });
} catch (e) {
  result.error = String(e && e.stack ? e.stack : e);
  code = 1;
} finally {
  await browser.close();
}
console.log(`RESULT ${JSON.stringify(result)}`);
process.exit(code);
