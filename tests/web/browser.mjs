// What every script driving pushlab's page shares (the tests, measure.mjs, limit.mjs,
// screenshot.mjs, training.mjs): Debian's chromium launched as the tests drive it, the wait for
// the app, and the watch of the frames drawn.
import { chromium } from "playwright-core";

/** Debian's chromium, headless, with WebGL2 on SwiftShader (docs/src/web.md says why). */
export function launch() {
  return chromium.launch({
    executablePath: process.env.PUSHLAB_CHROMIUM ?? "/usr/bin/chromium",
    // This machine's network is closed: no background connections, no first-run work.
    args: ["--no-sandbox", "--disable-background-networking", "--disable-component-update",
      "--disable-sync", "--no-first-run", "--disable-quic", "--use-angle=swiftshader",
      "--enable-unsafe-swiftshader"],
  });
}

/** Waits until the app drew a frame and nothing runs off the UI thread; returns what it shows. */
export async function settled(page, { timeout = 120_000, polling = 100 } = {}) {
  await page.waitForFunction(() => {
    const s = window.pushlab?.state();
    return s && !s.busy;
  }, null, { timeout, polling });
  return page.evaluate(() => window.pushlab.state());
}

/** Starts noting, at each of the browser's frames, the time since the one before and whether a
 * model was training then; `gapsWhileTraining` reads them back. A long gap is the page's thread
 * held. */
export async function watchFrameGaps(page) {
  await page.evaluate(() => {
    window.pushlab_gaps = [];
    let last = performance.now();
    const tick = (now) => {
      window.pushlab_gaps.push([now - last, window.pushlab.state().training]);
      last = now;
      requestAnimationFrame(tick);
    };
    requestAnimationFrame(tick);
  });
}

/** The gaps `watchFrameGaps` noted at frames drawn while a model trained, ms. */
export function gapsWhileTraining(page) {
  return page.evaluate(() => window.pushlab_gaps.filter(([, training]) => training !== null).map(([gap]) => gap));
}
