// Drives Debian's headless Chromium (playwright-core) to twin-web's page while the closed loop runs and approves a
// recommended lever as an operator does: signs in (basic authentication), types another name into the alarm
// form's user field (the authenticated user must win), waits for the approve button under the group's lever
// recommendation, clicks it, accepts the confirmation and waits for the page's answer. Reports `RESULT {json}`
// (the button's text, the confirmation's text, the answer's status, request id and text); the gtest judges the
// facts, this script fails (exit 1) only when it cannot carry out a step.
//   node drive_approve.mjs --url U --out DIR --chromium PATH --group G --user NAME --password P --typed-user NAME
// Screenshot: DIR/twin_web_approve.png (the recommendations card after the answer).
import fs from 'node:fs';
import path from 'node:path';
import { drive, parseArgs } from './drive_common.mjs';

const args = parseArgs('drive_approve', ['url', 'out', 'chromium', 'group', 'user', 'password', 'typed-user']);

await drive('drive_approve', args.chromium, async ({ page, result, step }) => {
  result.dialogs = [];
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
}, { username: args.user, password: args.password });
