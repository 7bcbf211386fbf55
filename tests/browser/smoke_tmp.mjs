import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { loadPlaywright, launchBrowser, startServer, stopServer } from './harness.mjs';
const playwright = loadPlaywright();
const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'smoke-'));
const context = await launchBrowser(playwright, path.join(tmp, 'profile'), { downloads: true });
const server = await startServer(tmp, { db: process.env.SMOKE_DB || undefined });
const page = context.pages()[0];
page.on('console', (m) => console.log('console', m.type(), m.text()));
page.on('pageerror', (e) => console.log('pageerror', e.message, e.stack));
const url = server.url;
for (const h of (process.env.SMOKE_PAGES || '#/compare').split(' ')) {
  await page.goto(`${url}/${h}`);
  await page.waitForTimeout(Number(process.env.SMOKE_WAIT || 4000));
  const name = h.replace(/[^a-z]/g, '_').slice(0, 30);
  await page.screenshot({ path: `/tmp/websmoke/${name}.png`, fullPage: true });
  console.log('points', await page.evaluate(() => [...document.querySelectorAll('.chart-box')].map((b) => `${b.dataset.testid}=${b.dataset.points}`).join(' ')));
  console.log('hash', await page.evaluate(() => location.hash));
}
await context.close();
await stopServer(server);
