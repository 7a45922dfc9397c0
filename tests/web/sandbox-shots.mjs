// The teachers' page's screenshots (docs/src/images/web-sandbox*.png): the sandbox in the page
// after a first push and two the ranking suggested, with the next suggestions drawn, then the
// score card after the reveal. In Debian's chromium as the tests drive it:
//   node tests/web/sandbox-shots.mjs URL OUT_DIR [QUERY]
// e.g. node tests/web/sandbox-shots.mjs http://127.0.0.1:8765/ ../../docs/src/images '?sandbox=5&object=box'
import { launch, settled } from "./browser.mjs";

const [site, out, query = "?sandbox=5&object=box"] = process.argv.slice(2);
const browser = await launch();
const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
await page.goto(site + query);
await settled(page);
const command = (obj) => page.evaluate((o) => window.pushlab.command(o), obj);
const done = (count) => page.waitForFunction((count) => {
  const s = window.pushlab.state();
  return !s.busy && s.sandbox.pushes === count && !s.sandbox.pushing;
}, count, { timeout: 120_000, polling: 50 });
const suggested = async () => {
  await command({ suggest: true });
  await page.waitForFunction(() => !window.pushlab.state().busy && window.pushlab.state().sandbox.suggested.length > 0,
    null, { timeout: 120_000, polling: 50 });
  const { com_std_after, ...push } = (await page.evaluate(() => window.pushlab.state())).sandbox.suggested[0];
  return push;
};

await command({ push: { face: "front", offset: 0, angle: 0, length: 0.1 } });
await done(1);
for (const count of [2, 3]) {
  await command({ push: await suggested() });
  await done(count);
}
await suggested();
await command({ guess: [0.01, -0.02] });
await settled(page);
await page.waitForTimeout(500);
await page.screenshot({ path: `${out}/web-sandbox.png` });
await command({ reveal: true });
await settled(page);
await page.waitForTimeout(500);
await page.screenshot({ path: `${out}/web-sandbox-score.png` });
await browser.close();
