// The guide's screenshots of the page (docs/src/images/web-*.png), in Debian's chromium as the
// tests drive it:   node tests/web/screenshot.mjs URL QUERY FRAME OUT.png [WIDTHxHEIGHT]
// e.g. node tests/web/screenshot.mjs http://127.0.0.1:8765/ '?demo=R2b%20COM&projector=1' 40 \
//        ../../docs/src/images/web-projector.png 1280x800
import { launch, settled } from "./browser.mjs";

const [site, query, frame, out, size = "1280x800"] = process.argv.slice(2);
const [width, height] = size.split("x").map(Number);
const browser = await launch();
const page = await browser.newPage({ viewport: { width, height } });
await page.goto(site + query);
await settled(page);
await page.evaluate((frame) => window.pushlab.command({ learn: true, seek: Number(frame) }), frame);
await settled(page);
await page.waitForTimeout(500);
await page.screenshot({ path: out });
await browser.close();
