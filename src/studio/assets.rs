//! The page's files, all inside the binary: nothing is fetched from
//! anywhere, and the page works offline. The WASM module is the runtime
//! crate compiled by `build.rs`.

/// One embedded file: its URL path, media type and bytes.
pub struct Asset {
    /// The path it is served at.
    pub path: &'static str,
    /// Its `Content-Type`.
    pub mime: &'static str,
    /// Its bytes.
    pub bytes: &'static [u8],
}

/// The runtime compiled to `wasm32-unknown-unknown` (`runtime-wasm/`).
pub const WASM: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/taxel_wasm.wasm"));

/// Every file the page is made of.
pub const ASSETS: &[Asset] = &[
    Asset { path: "/", mime: "text/html; charset=utf-8", bytes: include_bytes!("web/index.html") },
    Asset { path: "/studio.css", mime: "text/css; charset=utf-8", bytes: include_bytes!("web/studio.css") },
    Asset { path: "/studio.js", mime: "text/javascript; charset=utf-8", bytes: include_bytes!("web/studio.js") },
    Asset { path: "/player.js", mime: "text/javascript; charset=utf-8", bytes: include_bytes!("web/player.js") },
    Asset { path: "/taxel.wasm", mime: "application/wasm", bytes: WASM },
];

/// The embedded file served at `path`, if any.
pub fn find(path: &str) -> Option<&'static Asset> {
    let path = if path == "/index.html" { "/" } else { path };
    ASSETS.iter().find(|a| a.path == path)
}
