//! Builds the studio's WebAssembly runtime (`runtime-wasm/`, package
//! `taxel-wasm`) for `wasm32-unknown-unknown` during the normal build of the
//! binary, so that `taxel studio` embeds the module with no manual step
//! (`rust-toolchain.toml` names the target; where rustup did not install
//! it with the toolchain, as rustup 1.28 and later do not for a toolchain
//! already installed, this script asks rustup for it once).
//!
//! The module is built by a cargo of its own, in a target folder beside the
//! outer build's (`target/taxel-wasm`), shared by `cargo build`, `test`,
//! `clippy` and `doc`, so it is compiled once and then only checked.

use std::env;
use std::path::{Path, PathBuf};
use std::process::Command;

const TARGET: &str = "wasm32-unknown-unknown";

fn main() {
    let root = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    for watched in ["runtime-wasm", "runtime/src", "runtime/Cargo.toml", "format-spec/src", "format-spec/Cargo.toml"] {
        println!("cargo:rerun-if-changed={}", root.join(watched).display());
    }
    println!("cargo:rerun-if-changed={}", root.join("Cargo.lock").display());
    ensure_target();
    let target_dir = shared_target_dir(&out).unwrap_or_else(|| out.join("taxel-wasm"));
    let cargo = env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let mut cmd = Command::new(cargo);
    cmd.current_dir(&root)
        .args(["build", "--package", "taxel-wasm", "--lib", "--release", "--target", TARGET, "--target-dir"])
        .arg(&target_dir)
        // The outer build's wrappers and flags are for the host: clippy's
        // driver would lint the module instead of building it, and host
        // flags (`-C target-cpu=native`) do not apply to wasm32.
        .env_remove("RUSTC_WORKSPACE_WRAPPER")
        .env_remove("RUSTFLAGS")
        // WebAssembly SIMD (every current browser has it): the runtime's
        // portable SIMD (`wide`) plays a tala-map frame in 3.5-6.7 µs in V8
        // with it, 22-27 µs without (docs/studio.md).
        .env("CARGO_ENCODED_RUSTFLAGS", "-Ctarget-feature=+simd128")
        .env_remove("CARGO_TARGET_DIR")
        .env_remove("CARGO_BUILD_TARGET")
        // A small module: no debug information, and optimised across crates.
        .env("CARGO_PROFILE_RELEASE_DEBUG", "false")
        .env("CARGO_PROFILE_RELEASE_STRIP", "true")
        .env("CARGO_PROFILE_RELEASE_LTO", "true")
        .env("CARGO_PROFILE_RELEASE_CODEGEN_UNITS", "1")
        .env("CARGO_PROFILE_RELEASE_PANIC", "abort");
    let status = cmd.status().unwrap_or_else(|e| panic!("cannot run cargo to build the studio's WASM runtime: {e}"));
    if !status.success() {
        panic!(
            "building the studio's WASM runtime (taxel-wasm for {TARGET}) failed (above). \
             Is the target installed? `rustup target add {TARGET}` (rust-toolchain.toml names it)."
        );
    }
    let built = target_dir.join(TARGET).join("release").join("taxel_wasm.wasm");
    std::fs::copy(&built, out.join("taxel_wasm.wasm"))
        .unwrap_or_else(|e| panic!("cannot copy {}: {e}", built.display()));
}

/// Installs the wasm32 standard library through rustup when the compiler
/// has none: `rust-toolchain.toml` names the target, but rustup installs a
/// file's targets only with a toolchain it installs itself, so on a machine
/// whose stable toolchain came first, `cargo run --release` would stop here.
/// Without rustup (a distribution's Rust), the build's error says what to do.
fn ensure_target() {
    let rustc = env::var_os("RUSTC").unwrap_or_else(|| "rustc".into());
    let Some(sysroot) = Command::new(rustc)
        .args(["--print", "sysroot"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| PathBuf::from(String::from_utf8_lossy(&o.stdout).trim()))
    else {
        return;
    };
    if sysroot.join("lib/rustlib").join(TARGET).join("lib").is_dir() {
        return;
    }
    // Said once it is done: cargo repeats a build script's warnings on
    // every later build until the script runs again.
    match Command::new("rustup").args(["target", "add", TARGET]).status() {
        Ok(s) if s.success() => println!(
            "cargo:warning=the toolchain had no {TARGET} target: `rustup target add {TARGET}` installed it, \
             for the studio's WASM runtime"
        ),
        _ => println!("cargo:warning=`rustup target add {TARGET}` failed; the build below says what is missing"),
    }
}

/// `target/taxel-wasm` beside the outer build's profile folders, found from
/// `OUT_DIR` (`target/PROFILE/build/taxel-HASH/out`, or with a target
/// triple after `target/`); `None` when the layout is another.
fn shared_target_dir(out: &Path) -> Option<PathBuf> {
    let build = out.ancestors().nth(2)?;
    if build.file_name()? != "build" {
        return None;
    }
    let mut target = build.parent()?.parent()?;
    // `target/TRIPLE/PROFILE`: step past the triple too.
    if env::var_os("TARGET").is_some_and(|t| target.file_name() == Some(t.as_os_str())) {
        target = target.parent()?;
    }
    Some(target.join("taxel-wasm"))
}
