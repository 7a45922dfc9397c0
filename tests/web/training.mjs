// How the page behaves while a demo trains its model: how long the demo takes to settle, and the
// longest time between two of the browser's frames while the model trains (the page's thread held).
// Usage, from tests/web/ with the site served (bash scripts/web --serve):
//   node training.mjs http://127.0.0.1:8765/ [RUNS]
import { gapsWhileTraining, launch, settled, watchFrameGaps } from "./browser.mjs";

const site = process.argv[2] ?? "http://127.0.0.1:8765/";
const runs = Number(process.argv[3] ?? 3);
const browser = await launch();
for (let run = 0; run < runs; run++) {
  // A new page each run: nothing trained before is remembered.
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  await page.goto(site);
  await settled(page);
  await watchFrameGaps(page);
  const start = Date.now();
  await page.evaluate(() => window.pushlab.command({ demo: "R2b COM" }));
  await settled(page);
  const took = Date.now() - start;
  const training = await gapsWhileTraining(page);
  console.log(`demo settled in ${took} ms; ${training.length} frames drawn while training, the longest ${Math.max(...training).toFixed(0)} ms apart`);
  await page.close();
}
await browser.close();
