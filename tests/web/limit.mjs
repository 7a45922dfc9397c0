// How large a file the page can hold (docs/src/web.md, "Memory"): drops files of growing size named
// `big.mcap` (zeros: read whole into the page's files, then refused as not an MCAP file) and says
// for each whether the app read it and said why it is not a bag, or stopped.
//   node tests/web/limit.mjs URL [MEGABYTES...]
// against a site served by `bash scripts/web --serve`, in Debian's chromium as the tests drive it.
import { launch, settled } from "./browser.mjs";

const site = process.argv[2] ?? "http://127.0.0.1:8765/";
const sizes = process.argv.slice(3).map(Number);
const browser = await launch();
for (const megabytes of sizes.length ? sizes : [256, 512, 1024, 1536, 2048]) {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  const errors = [];
  page.on("pageerror", (e) => errors.push(String(e)));
  page.on("crash", () => errors.push("the tab crashed"));
  await page.goto(site);
  await settled(page);
  const start = Date.now();
  let outcome;
  try {
    await page.evaluate((bytes) => {
      const transfer = new DataTransfer();
      transfer.items.add(new File([new Uint8Array(bytes)], "big.mcap"));
      const canvas = document.getElementById("pushlab_canvas");
      for (const type of ["dragenter", "dragover", "drop"]) {
        canvas.dispatchEvent(new DragEvent(type, { dataTransfer: transfer, bubbles: true, cancelable: true }));
      }
    }, megabytes * 1024 * 1024);
    await page.waitForFunction(() => {
      const s = window.pushlab.state();
      return (s.error && s.error.includes("big.mcap")) || window.pushlab.panic();
    }, null, { timeout: 90_000, polling: 200 });
    const s = await page.evaluate(() => [window.pushlab.state().error, window.pushlab.panic()]);
    outcome = s[1] ? `panicked: ${s[1]}` : `read, then refused: ${s[0]}`;
  } catch (error) {
    const shown = await page.evaluate(() => {
      const s = window.pushlab.state();
      return `error ${s.error}, status ${s.status}, busy ${s.busy}, open ${s.open.length}`;
    }).catch((e) => String(e).split("\n")[0]);
    outcome = `stopped: ${errors.join("; ") || String(error).split("\n")[0]} (shown: ${shown})`;
  }
  console.log(`${megabytes} MB: ${outcome} (${((Date.now() - start) / 1000).toFixed(1)} s)`);
  await page.close().catch(() => {});
}
await browser.close();
