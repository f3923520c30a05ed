// What the Chromium driver scripts (drive_*.mjs) share: their command line, Debian's headless Chromium
// (playwright-core, no browser download), a first page that records every console error, page error and failed
// request, and the one line `RESULT {json}` the gtest judges. A driver fails (exit 1) only when it cannot carry
// out a step; a missing option exits 2.
import { chromium } from 'playwright-core';

// --key value pairs; every key in `required` must be given.
export function parseArgs(name, required) {
  const args = Object.fromEntries(process.argv.slice(2).reduce((acc, a, i, all) => {
    if (a.startsWith('--')) acc.push([a.slice(2), all[i + 1]]);
    return acc;
  }, []));
  for (const k of required) {
    if (!args[k]) { console.error(`${name}: --${k} is required`); process.exit(2); }
  }
  return args;
}

// Runs `steps({ browser, page, result, step })` on a fresh 1280x1000 page, then prints RESULT and exits.
// `credentials` ({ username, password }): twin-web's basic authentication for every request of the page.
export async function drive(name, chromiumPath, steps, credentials = null) {
  const result = { console_errors: [], page_errors: [], failed_requests: [], steps: [] };
  const step = (s) => { result.steps.push(s); console.log(`${name}: ${s}`); };
  const browser = await chromium.launch({
    executablePath: chromiumPath,
    headless: true,
    // root in a container: Chromium's sandbox needs user namespaces it may not have.
    args: ['--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage'],
  });
  let code = 0;
  try {
    const context = await browser.newContext({ viewport: { width: 1280, height: 1000 },
      ...(credentials ? { httpCredentials: credentials } : {}) });
    const page = await context.newPage();
    page.on('console', (m) => { if (m.type() === 'error') result.console_errors.push(m.text()); });
    page.on('pageerror', (e) => result.page_errors.push(String(e)));
    page.on('requestfailed', (r) => {
      // An event stream is cut when the page switches groups or the browser closes; anything else failing is a defect.
      if (new URL(r.url()).pathname !== '/api/events') result.failed_requests.push(`${r.url()}: ${r.failure()?.errorText}`);
    });
    await steps({ browser, page, result, step });
  } catch (e) {
    result.error = String(e && e.stack ? e.stack : e);
    code = 1;
  } finally {
    await browser.close();
  }
  console.log(`RESULT ${JSON.stringify(result)}`);
  process.exit(code);
}

// How far the page is wider than its window (0: no horizontal scrolling).
export const pageOverflowX = (page) => page.evaluate(() =>
  document.documentElement.scrollWidth - document.documentElement.clientWidth);
