// Drives Debian's headless Chromium (playwright-core) to twin-web's page after a closed-loop run and reads the
// Interventions card as an operator sees it: for the approved group (--group) every row's request id, status and
// cell texts and the count badge; for the unapproved group (--other) the number of intervention rows. Reports
// `RESULT {json}`; the gtest judges the facts, this script fails (exit 1) only when it cannot carry out a step.
//   node drive_interventions.mjs --url U --out DIR --chromium PATH --group G --other G2 [--user NAME --password P]
// (--user and --password: twin-web's basic authentication.)
// Screenshots: DIR/twin_web_interventions.png (the whole page), DIR/twin_web_interventions_card.png (the card).
import fs from 'node:fs';
import path from 'node:path';
import { drive, pageOverflowX, parseArgs } from './drive_common.mjs';

const args = parseArgs('drive_interventions', ['url', 'out', 'chromium', 'group', 'other']);

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

await drive('drive_interventions', args.chromium, async ({ page, result, step }) => {
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
  result.page_overflow_x = await pageOverflowX(page);
  // The other group's card once it has been rendered for that group (its placeholder row).
  result.other = await open(args.other, '#interventions tbody tr td.muted');
  step(`${args.other}: ${result.other.rows.length} row(s): ${result.other.body_text}`);
}, args.user ? { username: args.user, password: args.password } : null);
