//! The WASM runtime the studio embeds (served at `/taxel.wasm`), run in
//! Node.js (`wasm/run.mjs`: V8, the engine of the browsers the studio
//! serves), plays the tala map along its whole example trace (every 13th
//! tick), frame for frame, bit for bit, as the native runtime does; and
//! names what is under the finger as the native point lookup does.
//!
//! Without Node.js (20 or later) on the `PATH` these tests say so and pass,
//! unless `TAXEL_REQUIRE_NODE` is set (as `.ci/run` sets it), when they fail.

use std::io::{BufRead, BufReader, Write};
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};

use base64::Engine;
use base64::engine::general_purpose::STANDARD as BASE64;
use serde_json::{Value, json};
use taxel_format::lookup::PointLookup;
use taxel_format::{BundleView, Mm};
use taxel_runtime::latero::{LateroPlayer, Layer};
use taxel_runtime::trace::Trace;

use super::studio::Studio;

/// The module running in a Node.js process.
struct Wasm {
    child: Child,
    input: ChildStdin,
    output: BufReader<ChildStdout>,
}

/// Node.js, or `None` (after saying so) where it is not installed.
fn node() -> Option<&'static str> {
    let here = Command::new("node").arg("--version").output().is_ok_and(|o| o.status.success());
    if !here {
        assert!(std::env::var_os("TAXEL_REQUIRE_NODE").is_none(), "node is missing: install Node.js 20 or later");
        eprintln!("node (Node.js) not found: the WASM runtime's test in it is skipped here");
    }
    here.then_some("node")
}

impl Wasm {
    fn new(node: &str, module: &[u8], dir: &std::path::Path) -> Wasm {
        let path = dir.join("taxel.wasm");
        std::fs::write(&path, module).unwrap();
        let script = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/cli/wasm/run.mjs");
        let mut child = Command::new(node)
            .arg(script)
            .arg(&path)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .spawn()
            .expect("node starts");
        let (input, output) = (child.stdin.take().unwrap(), BufReader::new(child.stdout.take().unwrap()));
        Wasm { child, input, output }
    }

    /// Sends one request and returns its answer. An `f32` argument goes as
    /// the `f64` of its value, which JSON and JavaScript carry exactly.
    fn ask(&mut self, request: Value) -> Value {
        writeln!(self.input, "{request}").unwrap();
        let mut line = String::new();
        self.output.read_line(&mut line).unwrap();
        let mut answer: Value = serde_json::from_str(&line).unwrap_or_else(|e| panic!("{e}: {line:?} for {request}"));
        assert!(answer["err"].is_null(), "{request}: {}", answer["err"]);
        answer["ok"].take()
    }

    /// A fresh instance of the module.
    fn restart(&mut self) {
        self.ask(json!({"op": "new"}));
    }

    /// An export's `u32` result (`i32` in WebAssembly, signed in JavaScript).
    fn call(&mut self, name: &str, args: Value) -> u32 {
        self.ask(json!({"op": "call", "name": name, "args": args})).as_i64().unwrap() as u32
    }

    fn read(&mut self, at: u32, len: usize) -> Vec<u8> {
        let b64 = self.ask(json!({"op": "read", "at": at, "len": len}));
        BASE64.decode(b64.as_str().unwrap()).unwrap()
    }

    fn load(&mut self, bundle: &[u8]) -> u32 {
        let at = self.call("taxel_input", json!([bundle.len()]));
        self.ask(json!({"op": "write", "at": at, "b64": BASE64.encode(bundle)}));
        self.call("taxel_load", json!([]))
    }

    fn text(&mut self, len: u32) -> String {
        let at = self.call("taxel_text_ptr", json!([]));
        String::from_utf8(self.read(at, len as usize)).unwrap()
    }

    fn codes(&mut self, at: u32, n: usize) -> Vec<u16> {
        self.read(at, 2 * n).chunks_exact(2).map(|c| u16::from_le_bytes([c[0], c[1]])).collect()
    }
}

impl Drop for Wasm {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

#[test]
fn the_wasm_runtime_plays_a_long_trace_bit_for_bit_as_the_native_one() {
    let Some(node) = node() else { return };
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/map/tala-map.svg"), dir.path().join("tala.svg"))
        .unwrap();
    let s = Studio::start(dir.path());
    let wasm_bytes = s.get("/taxel.wasm").body;
    let v = s.post("/api/open?path=tala.svg", b"").json();
    let bundle = s.get(&format!("{}bundle", v["base"].as_str().unwrap())).body;
    drop(s);

    let mut wasm = Wasm::new(node, &wasm_bytes, dir.path());
    assert_eq!(wasm.load(b"not a bundle"), 1);
    let len = wasm.call("taxel_text_len", json!([]));
    assert!(wasm.text(len).starts_with("not a valid taxel bundle"));
    wasm.restart();
    assert_eq!(wasm.load(&bundle), 0);
    let len = wasm.call("taxel_info", json!([]));
    let info: serde_json::Value = serde_json::from_str(&wasm.text(len)).unwrap();
    assert_eq!(info["family"], "laterotactile");

    let plain = crate::plain(bundle.clone());
    let view = BundleView::parse(&plain).unwrap();
    let player = LateroPlayer::with_storage(&view, vec![Layer::EMPTY; view.chunk_count() as usize]).unwrap();
    let lookup = PointLookup::new(&view, PointLookup::DEFAULT_TOLERANCE_MM).unwrap();
    let n = player.actuator_count();
    let mut native = vec![0u16; n];
    let trace_csv = std::fs::read(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/traces/tala-map.csv")).unwrap();
    let trace = Trace::parse(&trace_csv[..]).unwrap();
    let rate = view.manifest().profile.rate_hz;
    let (mut frames, mut moving, mut names) = (0u64, 0u64, 0u64);
    let mut last = Vec::new();
    // Every 13th tick of the whole trace (62 s at 1 kHz): each frame is a
    // round trip to Node.js, and a frame depends on its tick and place
    // alone. The browser test compares every frame.
    for (tick, p) in trace.ticks(rate).step_by(13) {
        player.frame(tick, Mm(p.x_mm as f32), Mm(p.y_mm as f32), &mut native);
        let at =
            wasm.call("taxel_latero_frame", json!([tick.0 as f64, f64::from(p.x_mm as f32), f64::from(p.y_mm as f32)]));
        let played = wasm.codes(at, n);
        assert_eq!(played, native, "tick {} at ({}, {})", tick.0, p.x_mm, p.y_mm);
        frames += 1;
        moving += u64::from(played != last);
        last = played;
        // The name under the finger, at every 7th frame compared.
        if frames % 7 == 0 {
            let len = wasm.call("taxel_name_at", json!([p.x_mm, p.y_mm]));
            let want = lookup.under(p.x_mm, p.y_mm).map(|h| h.name()).unwrap_or_default();
            assert_eq!(wasm.text(len), want, "tick {}", tick.0);
            names += u64::from(!want.is_empty());
        }
    }
    // A long trace whose frames change, over named elements.
    assert!(frames > 4_000, "{frames}");
    assert!(moving > frames / 10, "{moving} of {frames}");
    assert!(names > 100, "{names}");
}

/// The studio builds each of the paper's shapes (a step and a quadric) for
/// `finger3`, stored as a tiled height field (format 4.6, gradients derived
/// in the player); the WASM runtime plays its trace sample for sample, bit
/// for bit, as the native finger player does.
#[test]
fn the_wasm_runtime_plays_a_tiled_height_field_bit_for_bit_as_the_native_one() {
    let Some(node) = node() else { return };
    use taxel_format::{Bundle, Chunk, HeightEncoding, Tick};
    use taxel_runtime::finger::{FingerPlayer, Touch};
    let examples = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/finger");
    let dir = tempfile::tempdir().unwrap();
    for shape in ["edge", "convex"] {
        std::fs::copy(format!("{examples}/{shape}.glb"), dir.path().join(format!("{shape}.glb"))).unwrap();
    }
    let s = Studio::start(dir.path());
    let wasm_bytes = s.get("/taxel.wasm").body;
    let mut wasm = Wasm::new(node, &wasm_bytes, dir.path());
    for shape in ["edge", "convex"] {
        let v = s.post(&format!("/api/open?path={shape}.glb&profile=finger3"), b"").json();
        let bundle = s.get(&format!("{}bundle", v["base"].as_str().unwrap())).body;
        // Format 4.6: the plain bundle's minor version, and the field's encoding.
        let plain = crate::plain(bundle.clone());
        assert_eq!(u16::from_le_bytes([plain[10], plain[11]]), 6, "{shape}");
        let tiled = Bundle::from_bytes(&bundle)
            .unwrap()
            .chunks
            .iter()
            .any(|c| matches!(c, Chunk::Height(h) if matches!(h.encoding, HeightEncoding::Tiled { .. })));
        assert!(tiled, "{shape}: a tiled height field");

        wasm.restart();
        assert_eq!(wasm.load(&bundle), 0, "{shape}");
        let len = wasm.call("taxel_info", json!([]));
        let info: serde_json::Value = serde_json::from_str(&wasm.text(len)).unwrap();
        assert_eq!(info["family"], "finger");
        let view = BundleView::parse(&plain).unwrap();
        let mut native = FingerPlayer::new(&view).unwrap();
        let trace = Trace::parse(std::fs::File::open(format!("{examples}/{shape}.trace.csv")).unwrap()).unwrap();
        let (mut touched, mut edges) = (0, 0);
        for p in trace.samples() {
            let tick = Tick((p.t_ms / 10.0).round() as u64);
            let (x, y) = (p.x_mm as f32, p.y_mm as f32);
            let f = native.sample(Touch { tick, x: Mm(x), y: Mm(y), contact: p.contact });
            let [l, d, r] = f.levels();
            let want = [l, d, r, f.period_ms, f.height, if f.on_edge { 1.0 } else { 0.0 }].map(f32::to_bits);
            let at = wasm
                .call("taxel_finger_sample", json!([tick.0 as f64, f64::from(x), f64::from(y), u32::from(p.contact)]));
            let buf = wasm.read(at, 24);
            let played: Vec<u32> = buf.chunks_exact(4).map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
            assert_eq!(played, want, "{shape}: t {} ms at ({x}, {y})", p.t_ms);
            touched += usize::from(f.active.is_some());
            edges += usize::from(f.on_edge);
        }
        // The traces cross the shapes: most samples drive an actuator, and
        // the edge's trace crosses its step.
        assert!(touched > trace.samples().len() / 2, "{shape}: {touched}");
        assert!(shape != "edge" || edges > 0, "{shape}: no step crossed");
    }
}
