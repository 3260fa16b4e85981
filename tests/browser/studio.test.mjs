// End-to-end tests of `taxel studio` in a real headless Chromium (Debian's
// `chromium`), driven by playwright-core; axe-core checks every view.
// Run by .ci/run on the taxel `cargo test` built (TAXEL_BIN names the binary):
//   cd tests/browser && npm ci && TAXEL_BIN=../../target/debug/taxel npm test
// Screenshots go to target/studio-screens/ for people to look at.

import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { spawn, spawnSync, execFileSync } from "node:child_process";
import { mkdtempSync, copyFileSync, readFileSync, writeFileSync, mkdirSync } from "node:fs";
import { tmpdir } from "node:os";
import { join, resolve, dirname } from "node:path";
import { fileURLToPath } from "node:url";
import { createRequire } from "node:module";
import { chromium } from "playwright-core";

const here = dirname(fileURLToPath(import.meta.url));
const repo = resolve(here, "../..");
const taxel = resolve(process.env.TAXEL_BIN || join(repo, "target/debug/taxel"));
const chromiumPath = process.env.CHROMIUM || "/usr/bin/chromium";
const axeSource = readFileSync(createRequire(import.meta.url).resolve("axe-core/axe.min.js"), "utf8");
const shots = join(repo, "target/studio-screens");
mkdirSync(shots, { recursive: true });

const dir = mkdtempSync(join(tmpdir(), "taxel-studio-"));
const map = join(dir, "tala-map.svg");
copyFileSync(join(repo, "examples/map/tala-map.svg"), map);
// The same map with no annotation: the automatic style sheet styles it.
const plain = join(dir, "tala-plain.svg");
copyFileSync(join(repo, "examples/map/tala-plain.svg"), plain);

let server;
let url;
let browser;

before(async () => {
  server = spawn(taxel, ["studio", dir, "--no-open", "--port", "0"], { stdio: ["ignore", "pipe", "inherit"] });
  url = await new Promise((ok, fail) => {
    let out = "";
    server.stdout.on("data", (d) => {
      out += d;
      const m = /http:\/\/[0-9.:]+\//.exec(out);
      if (m) ok(m[0]);
    });
    server.on("exit", (code) => fail(new Error(`taxel studio exited with ${code}: ${out}`)));
  });
  browser = await chromium.launch({
    executablePath: chromiumPath,
    headless: true,
    args: [
      "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
      "--disable-background-networking", "--disable-component-update", "--disable-sync",
    ],
  });
});

after(async () => {
  await browser?.close();
  server?.kill();
});

async function newPage(viewport = { width: 1280, height: 900 }) {
  const context = await browser.newContext({ viewport, acceptDownloads: true });
  const page = await context.newPage();
  page.on("pageerror", (e) => assert.fail(`page error: ${e.message}`));
  return page;
}

// axe-core, evaluated in the page (the page's policy allows no injected script tag).
async function axe(page, name) {
  await page.evaluate(axeSource);
  const result = await page.evaluate(() => window.axe.run(document, { resultTypes: ["violations"] }));
  const violations = result.violations.map((v) => `${v.id}: ${v.help} (${v.nodes.map((n) => n.target).join(" | ")})`);
  assert.deepEqual(violations, [], `axe on ${name}`);
}

async function openMap(page, suffix = "") {
  await page.goto(url + suffix);
  await page.getByRole("button", { name: "tala-map.svg" }).click();
  await page.waitForFunction(() => document.getElementById("status").textContent.startsWith("Built tala-map.svg"));
}

function cli(args) {
  return execFileSync(taxel, args, { encoding: "buffer", stdio: ["ignore", "pipe", "pipe"] });
}

test("the teacher opens a drawing and reads its diagnostics as the command line groups them", async () => {
  const page = await newPage();
  await openMap(page);
  const lines = await page.$$eval("#diagnostics button", (bs) => bs.map((b) => b.textContent));
  assert.ok(lines.length > 0, "the map has diagnostics");
  // `taxel check` prints the same account (exit 1 when there are errors).
  const check = spawnSync(taxel, ["check", map], { encoding: "utf8" });
  const cliText = (check.stdout + check.stderr).replaceAll(map, "tala-map.svg");
  for (const l of lines) {
    assert.ok(cliText.includes(l.split("\n")[0]), `the CLI says it too: ${l}`);
  }
  // Selecting a diagnostic outlines its elements (those the bundle has) on both pictures.
  let outlined = 0;
  for (const button of await page.locator("#diagnostics button").all()) {
    // The status this click leads to, not the last one's.
    const before = await page.$eval("#status", (s) => s.textContent);
    await button.click();
    assert.equal(await button.getAttribute("aria-pressed"), "true");
    await page.waitForFunction(
      (before) => {
        const now = document.getElementById("status").textContent;
        return now !== before && /elements shown|no element to show/.test(now);
      },
      before,
    );
    const marks = await page.$$eval("#drawing-marks > *", (m) => m.length);
    const felt = await page.$$eval("#preview-marks > *", (m) => m.length);
    assert.equal(marks, felt);
    outlined += marks;
    if (marks) break;
  }
  assert.ok(outlined > 0, "some diagnostic's elements are outlined");
  await page.screenshot({ path: join(shots, "teacher.png"), fullPage: true });
  await axe(page, "the teacher's view");
});

test("the student moves the finger by keyboard, hears the element, and the frame is taxel play's", async () => {
  const page = await newPage();
  await openMap(page);
  await page.getByRole("button", { name: "Explore" }).click();
  await page.focus("#surface");
  await page.keyboard.press("Home");
  // From the centre (55, 30) to (25, 15): 6 steps of 5 mm left, 3 up.
  for (let i = 0; i < 6; i++) await page.keyboard.press("Shift+ArrowLeft");
  for (let i = 0; i < 3; i++) await page.keyboard.press("Shift+ArrowUp");
  await page.keyboard.press("ArrowRight");
  await page.keyboard.press("ArrowLeft");
  assert.equal(await page.textContent("#pos"), "25.0, 15.0 mm");
  assert.equal(await page.textContent("#under"), "ash province");
  assert.equal(await page.getAttribute("#under", "aria-live"), "polite");
  // The fragment follows the finger (written at most every 200 ms, the last place always).
  await page.waitForURL(/#at=25,15$/);
  // The frame drawn, held still, against `taxel play` at that tick and place.
  await page.check("#pause");
  await page.waitForTimeout(100);
  const frame = await page.$eval("#frame", (c) => ({ ...c.dataset }));
  assert.equal(frame.x, "25");
  assert.equal(frame.y, "15");
  const bundle = join(dir, "play.taxel");
  cli(["build", map, "-o", bundle]);
  const trace = join(dir, "at.csv");
  writeFileSync(trace, `t_ms,x_mm,y_mm\n${frame.tick},25,15\n`);
  const played = cli(["play", bundle, "--trace", trace]).toString().trim().split("\n");
  assert.equal(played.length, 2, played.join("\n"));
  assert.equal(played[1], `${frame.tick},${frame.values}`);
  await page.screenshot({ path: join(shots, "explore.png"), fullPage: true });
  await axe(page, "the explore view");
});

test("the page's WASM runtime plays 30 s of exploration bit for bit as taxel play", async () => {
  const page = await newPage();
  await openMap(page);
  // One sample a millisecond (1 kHz, stress2's rate): each tick is a sample, exactly.
  const n = 30000;
  const xs = [];
  const ys = [];
  let csv = "t_ms,x_mm,y_mm\n";
  for (let k = 0; k < n; k++) {
    const phase = (k % 6000) / 3000;
    const x = (2 + 106 * (phase < 1 ? phase : 2 - phase)).toFixed(3);
    const y = (2 + (56 * k) / n).toFixed(3);
    xs.push(Number(x));
    ys.push(Number(y));
    csv += `${k},${x},${y}\n`;
  }
  const trace = join(dir, "sweep.csv");
  writeFileSync(trace, csv);
  const bundle = join(dir, "sweep.taxel");
  cli(["build", map, "-o", bundle]);
  const frames = join(dir, "sweep-frames.csv");
  cli(["play", bundle, "--trace", trace, "--out", frames]);
  const played = readFileSync(frames, "utf8").trim().split("\n").slice(1);
  const ours = await page.evaluate(({ xs, ys }) => {
    const p = window.taxelStudio.player;
    const lines = [];
    for (let k = 0; k < xs.length; k++) lines.push(`${k},${p.lateroFrame(k, xs[k], ys[k]).join(",")}`);
    return lines;
  }, { xs, ys });
  assert.equal(ours.length, n);
  assert.equal(played.length, n);
  let differ = 0;
  for (let k = 0; k < n; k++) differ += ours[k] !== played[k];
  assert.equal(differ, 0, `first difference: ${ours.find((l, k) => l !== played[k])}`);
  assert.ok(new Set(played.map((l) => l.slice(l.indexOf(",")))).size > n / 10, "the frames change along the sweep");
});

test("a shared #at=X,Y places the finger", async () => {
  const page = await newPage({ width: 390, height: 844 });
  await openMap(page, "#at=33,16.5");
  await page.getByRole("button", { name: "Explore" }).click();
  assert.equal(await page.textContent("#pos"), "33.0, 16.5 mm");
  assert.equal(await page.textContent("#under"), "coast and province borders");
  await page.screenshot({ path: join(shots, "phone-explore.png"), fullPage: true });
  await axe(page, "the explore view on a phone");
});

test("the bundle downloaded is taxel build's byte for byte", async () => {
  const page = await newPage();
  await openMap(page);
  const [download] = await Promise.all([
    page.waitForEvent("download"),
    page.getByRole("link", { name: /^Bundle/ }).click(),
  ]);
  const saved = join(dir, "downloaded.taxel");
  await download.saveAs(saved);
  const built = join(dir, "built.taxel");
  cli(["build", map, "-o", built]);
  assert.ok(readFileSync(saved).equals(readFileSync(built)), "the studio's bundle is taxel build's");
});

test("a style change rebuilds the copy, and its bundle is taxel build's of that copy", async () => {
  const page = await newPage();
  await openMap(page);
  const before = await page.textContent("#summary");
  await page.fill("#element", "path1");
  await page.selectOption("#style-kind", "dots");
  await page.click("#apply");
  await page.waitForFunction(() => document.querySelector("#copy a") !== null);
  const after = await page.textContent("#summary");
  assert.notEqual(after, before);
  const [copy] = await Promise.all([page.waitForEvent("download"), page.click("#copy a")]);
  const copyPath = join(dir, "copy.svg");
  await copy.saveAs(copyPath);
  assert.match(readFileSync(copyPath, "utf8"), /<path data-tactile="dots\(\)"[^>]*id="path1"/);
  const [bundle] = await Promise.all([
    page.waitForEvent("download"),
    page.getByRole("link", { name: /^Bundle/ }).click(),
  ]);
  const saved = join(dir, "styled.taxel");
  await bundle.saveAs(saved);
  const built = join(dir, "copy.taxel");
  cli(["build", copyPath, "-o", built]);
  assert.ok(readFileSync(saved).equals(readFileSync(built)), "the rebuilt bundle is taxel build's of the copy");
  await page.screenshot({ path: join(shots, "restyled.png"), fullPage: true });
});

test("every element of one fill colour restyled: a style sheet, and the bundle is taxel build's with it", async () => {
  const page = await newPage();
  await page.goto(url);
  await page.getByRole("button", { name: "tala-plain.svg" }).click();
  await page.waitForFunction(() => document.getElementById("status").textContent.startsWith("Built tala-plain.svg"));
  const before = await page.textContent("#summary");
  // Keyboard alone: the radio button, the colour, the style, the button.
  await page.focus("#target-element");
  await page.keyboard.press("ArrowDown");
  assert.equal(await page.isChecked("#target-fill"), true);
  await page.waitForFunction(() => document.querySelectorAll("#fill option").length > 0);
  const colours = await page.$$eval("#fill option", (os) => os.map((o) => o.value));
  assert.ok(colours.includes("#e41a1c"), colours.join(" "));
  await page.selectOption("#fill", "#e41a1c");
  await page.selectOption("#style-kind", "dots");
  await page.focus("#apply");
  await page.keyboard.press("Enter");
  await page.waitForFunction(() => /tactile\.toml/.test(document.getElementById("copy").textContent));
  assert.notEqual(await page.textContent("#summary"), before);
  await axe(page, "the teacher's view, styling by fill colour");
  await page.screenshot({ path: join(shots, "fill-restyled.png"), fullPage: true });

  const [download] = await Promise.all([
    page.waitForEvent("download"),
    page.getByRole("link", { name: /style sheet/ }).click(),
  ]);
  assert.equal(download.suggestedFilename(), "tala-plain.tactile.toml");
  const sheetPath = join(dir, "tala-plain.tactile.toml");
  await download.saveAs(sheetPath);
  const sheet = readFileSync(sheetPath, "utf8");
  // It starts from the automatic sheet as decided for this drawing (the
  // drawing had no annotation), as `taxel style auto` prints it, and ends
  // with the colour's rule.
  const decided = cli(["style", "auto", plain]).toString();
  assert.ok(sheet.startsWith(decided), "the sheet starts from taxel style auto's");
  assert.match(sheet.slice(decided.length), /\[\[rule\]\]\nfill = "#e41a1c"\ntactile = "dots\(\)"\n$/);

  const [bundle] = await Promise.all([
    page.waitForEvent("download"),
    page.getByRole("link", { name: /^Bundle/ }).click(),
  ]);
  const saved = join(dir, "plain-styled.taxel");
  await bundle.saveAs(saved);
  const built = join(dir, "plain-sheet.taxel");
  cli(["build", plain, "--style", sheetPath, "-o", built]);
  assert.ok(readFileSync(saved).equals(readFileSync(built)), "the rebuilt bundle is taxel build's with the sheet");
  const unstyled = join(dir, "plain.taxel");
  cli(["build", plain, "-o", unstyled]);
  assert.ok(!readFileSync(saved).equals(readFileSync(unstyled)), "the change made another bundle");
});

test("a profile file chosen in the page builds as taxel build --profile FILE; a bad one says why", async () => {
  const page = await newPage();
  await openMap(page);
  // Stress2 under another name on a wider surface.
  const text = readFileSync(join(repo, "format-spec/profiles/stress2.toml"), "utf8")
    .replace('name = "stress2"', 'name = "classroom"')
    .replace("width_mm = 110", "width_mm = 130");
  const good = join(dir, "classroom.toml");
  writeFileSync(good, text);
  await page.setInputFiles("#profile-file", good);
  await page.waitForFunction(() => /for classroom/.test(document.getElementById("summary").textContent));
  assert.equal(await page.$eval("#profile", (s) => s.selectedOptions[0].textContent), "classroom (laterotactile, from classroom.toml)");
  const [download] = await Promise.all([
    page.waitForEvent("download"),
    page.getByRole("link", { name: /^Bundle/ }).click(),
  ]);
  const saved = join(dir, "classroom-studio.taxel");
  await download.saveAs(saved);
  const built = join(dir, "classroom-cli.taxel");
  cli(["build", map, "--profile", good, "-o", built]);
  assert.ok(readFileSync(saved).equals(readFileSync(built)), "the bundle is taxel build --profile FILE's");

  // A profile without its surface: the command line's message, beside the control.
  const bad = join(dir, "broken.toml");
  writeFileSync(bad, text.replace(/\[surface\][^[]*$/, ""));
  const run = spawnSync(taxel, ["build", map, "--profile", bad, "-o", join(dir, "x.taxel")], { encoding: "utf8" });
  assert.notEqual(run.status, 0);
  const why = run.stderr.trim().split(bad)[1];
  assert.ok(why && why.length > 3, run.stderr);
  await page.setInputFiles("#profile-file", bad);
  await page.waitForFunction(() => !document.getElementById("profile-error").hidden);
  const shown = await page.textContent("#profile-error");
  assert.ok(shown.includes(`broken.toml${why}`), `${shown} says ${why}`);
  assert.equal(await page.getAttribute("#profile-file", "aria-invalid"), "true");
  assert.match(await page.textContent("#status"), /broken\.toml was not used/);
  // The last good build stays.
  assert.match(await page.textContent("#summary"), /for classroom/);
  await axe(page, "the teacher's view with a refused profile file");
});
