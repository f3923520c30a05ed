// Drives Debian's headless Chromium (playwright-core) to twin-web's page after a run that left open alarms, and
// acknowledges one as an operator would: types a user name, clicks the alarm's Acknowledge button (the page POSTs
// it with the CSRF token it holds), waits for the answer and for the page to show the alarm acknowledged and the
// alarm-system line to count one unacknowledged alarm less. Reports `RESULT {json}`; the gtest judges the facts,
// this script fails (exit 1) only when it cannot carry out a step.
//   node drive_alarm_action.mjs --url U --out DIR --chromium PATH --user NAME
// Screenshots: DIR/twin_web_alarm_action.png (the whole page), DIR/twin_web_alarm_action_card.png (the alarm card).
import fs from 'node:fs';
import path from 'node:path';
import { drive, pageOverflowX, parseArgs } from './drive_common.mjs';

const args = parseArgs('drive_alarm_action', ['url', 'out', 'chromium', 'user']);

const rowOf = (id) => `#alarms tbody tr[data-alarm-id="${id}"]`;

await drive('drive_alarm_action', args.chromium, async ({ page, result, step }) => {
  await page.goto(args.url, { waitUntil: 'load' });
  step('page loaded');
  await page.waitForSelector('#alarms tbody tr[data-alarm-id] button.aa.ack', { timeout: 30000 });
  const health = () => page.evaluate(() => document.getElementById('alarm-health').textContent);
  const handling = (id) => page.evaluate((sel) => {
    const h = document.querySelector(`${sel} .handling`);
    return h ? { text: h.querySelector('.handling-state').textContent, acknowledged: h.dataset.acknowledged,
      buttons: [...h.querySelectorAll('button')].map((b) => b.textContent) } : null;
  }, rowOf(id));
  result.alarm_id = await page.evaluate(() =>
    document.querySelector('#alarms tbody tr[data-alarm-id] button.aa.ack').closest('tr').dataset.alarmId);
  result.open_rows = await page.evaluate(() => document.querySelectorAll('#alarms tbody tr[data-alarm-id]').length);
  result.before = await handling(result.alarm_id);
  result.health_before = await health();
  step(`acknowledging ${result.alarm_id} (${result.before && result.before.text}); ${result.health_before}`);

  await page.fill('#aa-user', args.user);
  await page.click(`${rowOf(result.alarm_id)} button.aa.ack`);
  await page.waitForFunction(() => !['idle', 'sending'].includes(document.getElementById('aa-result').dataset.status),
    null, { timeout: 30000 });
  result.ack_status = await page.evaluate(() => document.getElementById('aa-result').dataset.status);
  result.ack_text = await page.evaluate(() => document.getElementById('aa-result').textContent);
  step(`answer: ${result.ack_status}: ${result.ack_text}`);

  // The page shows it when the result (alarm_action_result) and the new status line (asset_status) reached twin-web.
  await page.waitForFunction((sel) => {
    const h = document.querySelector(`${sel} .handling`);
    return h && h.dataset.acknowledged === 'true';
  }, rowOf(result.alarm_id), { timeout: 20000 });
  await page.waitForFunction((before) => document.getElementById('alarm-health').textContent !== before,
    result.health_before, { timeout: 20000 });
  result.after = await handling(result.alarm_id);
  result.health_after = await health();
  step(`shown: ${result.after.text}; ${result.health_after}`);

  fs.mkdirSync(args.out, { recursive: true });
  result.screenshot = path.join(args.out, 'twin_web_alarm_action.png');
  await page.screenshot({ path: result.screenshot, fullPage: true });
  result.screenshot_card = path.join(args.out, 'twin_web_alarm_action_card.png');
  await page.locator('#alarms').locator('xpath=ancestor::section').screenshot({ path: result.screenshot_card });
  result.page_overflow_x = await pageOverflowX(page);
});
