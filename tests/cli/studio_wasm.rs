//! The WASM runtime the studio embeds (served at `/taxel.wasm`), run in a
//! WebAssembly interpreter (wasmi), plays the tala map along its whole
//! example trace (every 13th tick), frame for frame, bit for bit, as the native runtime does;
//! and names what is under the finger as the native point lookup does.

use taxel_format::lookup::PointLookup;
use taxel_format::{BundleView, Mm};
use taxel_runtime::latero::{LateroPlayer, Layer};
use taxel_runtime::trace::Trace;
use wasmi::{Engine, Instance, Linker, Memory, Module, Store};

use super::studio::Studio;

struct Wasm {
    store: Store<()>,
    instance: Instance,
    memory: Memory,
}

impl Wasm {
    fn new(bytes: &[u8]) -> Wasm {
        let engine = Engine::default();
        let module = Module::new(&engine, bytes).unwrap();
        let mut store = Store::new(&engine, ());
        let instance = Linker::<()>::new(&engine).instantiate_and_start(&mut store, &module).unwrap();
        let memory = instance.get_memory(&store, "memory").unwrap();
        Wasm { store, instance, memory }
    }

    fn call<P: wasmi::WasmParams, R: wasmi::WasmResults>(&mut self, name: &str, args: P) -> R {
        let f = self.instance.get_typed_func::<P, R>(&self.store, name).unwrap();
        f.call(&mut self.store, args).unwrap()
    }

    fn load(&mut self, bundle: &[u8]) -> u32 {
        let at: u32 = self.call("taxel_input", bundle.len() as u32);
        self.memory.write(&mut self.store, at as usize, bundle).unwrap();
        self.call("taxel_load", ())
    }

    fn text(&mut self, len: u32) -> String {
        let at: u32 = self.call("taxel_text_ptr", ());
        let mut buf = vec![0; len as usize];
        self.memory.read(&self.store, at as usize, &mut buf).unwrap();
        String::from_utf8(buf).unwrap()
    }

    fn codes(&mut self, at: u32, n: usize) -> Vec<u16> {
        let mut buf = vec![0u8; 2 * n];
        self.memory.read(&self.store, at as usize, &mut buf).unwrap();
        buf.chunks_exact(2).map(|c| u16::from_le_bytes([c[0], c[1]])).collect()
    }
}

#[test]
fn the_wasm_runtime_plays_a_long_trace_bit_for_bit_as_the_native_one() {
    // The interpreter's frames in a debug build need more than a test thread's 2 MiB.
    std::thread::Builder::new().stack_size(64 << 20).spawn(play_the_tala_trace).unwrap().join().unwrap();
}

fn play_the_tala_trace() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(concat!(env!("CARGO_MANIFEST_DIR"), "/examples/map/tala-map.svg"), dir.path().join("tala.svg"))
        .unwrap();
    let s = Studio::start(dir.path());
    let wasm_bytes = s.get("/taxel.wasm").body;
    let v = s.post("/api/open?path=tala.svg", b"").json();
    let bundle = s.get(&format!("{}bundle", v["base"].as_str().unwrap())).body;
    drop(s);

    let mut wasm = Wasm::new(&wasm_bytes);
    assert_eq!(wasm.load(b"not a bundle"), 1);
    let len: u32 = wasm.call("taxel_text_len", ());
    assert!(wasm.text(len).starts_with("not a valid taxel bundle"));
    let mut wasm = Wasm::new(&wasm_bytes);
    assert_eq!(wasm.load(&bundle), 0);
    let len: u32 = wasm.call("taxel_info", ());
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
    // Every 13th tick of the whole trace (62 s at 1 kHz): the interpreter in
    // a test build plays a few hundred frames a second, and a frame depends on
    // its tick and place alone. The browser test compares every frame.
    for (tick, p) in trace.ticks(rate).step_by(13) {
        player.frame(tick, Mm(p.x_mm as f32), Mm(p.y_mm as f32), &mut native);
        let at: u32 = wasm.call("taxel_latero_frame", (tick.0 as f64, p.x_mm as f32, p.y_mm as f32));
        let played = wasm.codes(at, n);
        assert_eq!(played, native, "tick {} at ({}, {})", tick.0, p.x_mm, p.y_mm);
        frames += 1;
        moving += u64::from(played != last);
        last = played;
        // The name under the finger, at every 7th frame compared.
        if frames % 7 == 0 {
            let len: u32 = wasm.call("taxel_name_at", (p.x_mm, p.y_mm));
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

#[test]
fn the_wasm_runtime_plays_a_tiled_height_field_bit_for_bit_as_the_native_one() {
    // Loading a tiled field runs long loops in one call, and the interpreter's
    // handlers (not tail calls in a test build) take stack for each: 64 MiB overflow.
    std::thread::Builder::new().stack_size(1 << 30).spawn(play_the_finger_traces).unwrap().join().unwrap();
}

/// The studio builds each of the paper's shapes (a step and a quadric) for
/// `finger3`, stored as a tiled height field (format 4.6, gradients derived
/// in the player); the WASM runtime plays its trace sample for sample, bit
/// for bit, as the native finger player does.
fn play_the_finger_traces() {
    use taxel_format::{Bundle, Chunk, HeightEncoding, Tick};
    use taxel_runtime::finger::{FingerPlayer, Touch};
    let examples = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/finger");
    let dir = tempfile::tempdir().unwrap();
    for shape in ["edge", "convex"] {
        std::fs::copy(format!("{examples}/{shape}.glb"), dir.path().join(format!("{shape}.glb"))).unwrap();
    }
    let s = Studio::start(dir.path());
    let wasm_bytes = s.get("/taxel.wasm").body;
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

        let mut wasm = Wasm::new(&wasm_bytes);
        assert_eq!(wasm.load(&bundle), 0, "{shape}");
        let len: u32 = wasm.call("taxel_info", ());
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
            let at: u32 = wasm.call("taxel_finger_sample", (tick.0 as f64, x, y, u32::from(p.contact)));
            let mut buf = [0u8; 24];
            wasm.memory.read(&wasm.store, at as usize, &mut buf).unwrap();
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
