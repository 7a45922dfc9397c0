// What every script driving pushlab's page shares (the tests, measure.mjs, limit.mjs,
// screenshot.mjs): Debian's chromium launched as the tests drive it, and the wait for the app.
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
