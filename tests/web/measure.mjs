// The page's figures for the guide's performance page (docs/src/performance.md, "The page"):
//   node tests/web/measure.mjs URL [MIT_FOLDER]
// against a site served by `bash scripts/web --serve`, in Debian's chromium as the tests drive it.
import { readdirSync, readFileSync } from "node:fs";
import { launch, settled } from "./browser.mjs";

const site = process.argv[2] ?? "http://127.0.0.1:8765/";
const mit = process.argv[3];
const browser = await launch();
const settle = (page) => settled(page, { polling: 20 });

// Navigation to the first frame drawn (the hook's state exists once a frame was drawn).
const firsts = [];
for (let run = 0; run < 5; run++) {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  const start = Date.now();
  await page.goto(site);
  await page.waitForFunction(() => window.pushlab?.state() !== null && window.pushlab?.state() !== undefined, null, { timeout: 60_000, polling: 10 });
  firsts.push(Date.now() - start);
  await page.close();
}
console.log(`first frame drawn after navigation: ${firsts.join(", ")} ms`);

// Playing the first sample push with learning on: the main thread's busy time per frame drawn (a
// CPU profile: everything but idle), and eframe's own CPU figure per frame.
const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
await page.goto(site);
await settle(page);
await page.evaluate(() => window.pushlab.command({ learn: true, play: true }));
await page.waitForTimeout(500);
const cdp = await page.context().newCDPSession(page);
await cdp.send("Profiler.enable");
const before = await page.evaluate(() => window.pushlab.state());
const meter = [];
await cdp.send("Profiler.start");
for (let i = 0; i < 20; i++) {
  await page.waitForTimeout(200);
  meter.push((await page.evaluate(() => window.pushlab.state())).frame_cpu_ms);
}
const { profile } = await cdp.send("Profiler.stop");
const after = await page.evaluate(() => window.pushlab.state());
const idle = new Set(profile.nodes.filter((n) => ["(idle)", "(program)", "(garbage collector)"].includes(n.callFrame.functionName) && n.callFrame.functionName === "(idle)").map((n) => n.id));
let busyUs = 0;
profile.samples.forEach((id, i) => { if (!idle.has(id)) busyUs += profile.timeDeltas[i] ?? 0; });
const drawn = after.frames_drawn - before.frames_drawn;
meter.sort((a, b) => a - b);
console.log(`playing with learning: ${drawn} frames drawn in 4 s, recording frame ${before.frame} -> ${after.frame}; ` +
  `main thread busy ${(busyUs / 1000 / drawn).toFixed(1)} ms per frame drawn; ` +
  `eframe's CPU per frame median ${meter[10].toFixed(1)} ms (min ${meter[0].toFixed(1)}, max ${meter[19].toFixed(1)})`);

// The MIT files dropped at once.
if (mit) {
  const files = readdirSync(mit).filter((f) => f.endsWith(".h5") || f.endsWith(".json"));
  const payload = files.map((f) => [f, readFileSync(`${mit}/${f}`).toString("base64")]);
  const count = (await page.evaluate(() => window.pushlab.state())).open.length;
  const start = Date.now();
  await page.evaluate((files) => {
    const transfer = new DataTransfer();
    for (const [name, b64] of files) {
      const bytes = Uint8Array.from(atob(b64), (c) => c.charCodeAt(0));
      transfer.items.add(new File([bytes], name));
    }
    const canvas = document.getElementById("pushlab_canvas");
    for (const type of ["dragenter", "dragover", "drop"]) {
      canvas.dispatchEvent(new DragEvent(type, { dataTransfer: transfer, bubbles: true, cancelable: true }));
    }
  }, payload);
  await page.waitForFunction((count) => window.pushlab.state().open.length > count, count, { timeout: 120_000, polling: 10 });
  await settle(page);
  const s = await page.evaluate(() => window.pushlab.state());
  console.log(`${files.length} MIT files dropped: ${s.open.length - count} recordings open after ${Date.now() - start} ms; error: ${s.error}`);
}
await browser.close();
