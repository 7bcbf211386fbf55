import fs from 'node:fs';
import os from 'node:os';
import path from 'node:path';
import { loadPlaywright, launchBrowser, startServer, stopServer } from './harness.mjs';
const playwright = loadPlaywright();
const tmp = fs.mkdtempSync(path.join(os.tmpdir(), 'smoke-'));
const context = await launchBrowser(playwright, path.join(tmp, 'profile'), { downloads: true });
const server = await startServer(tmp, { db: process.env.SMOKE_DB || undefined });
const page = context.pages()[0];
page.on('pageerror', (e) => console.log('pageerror', e.message, e.stack));
page.on('console', (m) => m.type() === 'error' && console.log('console', m.text()));
await page.goto(`${server.url}/#/compare`);
await page.waitForFunction(() => Number(document.querySelector('[data-testid=chart-times]')?.dataset.points) > 0);
for (const [id, what] of [['chart-times-0', 'svg'], ['chart-task-sizes', 'svg'], ['chart-times-0', 'png'], ['chart-task-sizes', 'png'], ['chart-solved-time', 'svg']]) {
  const [dl] = await Promise.all([page.waitForEvent('download'), page.locator(`[data-testid=${id}-${what}]`).click()]);
  await dl.saveAs(`/tmp/websmoke/${id}.${what}`);
}
for (const id of ['chart-times-0', 'chart-task-sizes', 'chart-solved-time']) {
  await page.goto(`file:///tmp/websmoke/${id}.svg`);
  await page.setViewportSize({ width: 700, height: 520 });
  await page.screenshot({ path: `/tmp/websmoke/${id}-svg.png` });
}
await context.close();
await stopServer(server);
