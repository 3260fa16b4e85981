//! liblouis, opened at run time: the only module of taxel with `unsafe`
//! code, all of it calls into the C library through the few functions
//! declared here.
//!
//! liblouis (LGPL-2.1+) is used as a system library: it is never linked at
//! build time, so taxel builds and runs without it (the built-in UEB grade 1
//! is used then). The library is not thread-safe (its table cache and index
//! are global), so every call goes through one process-wide lock.
//!
//! Safety, for every `unsafe` block below: the symbols are looked up by
//! name and given the signatures of liblouis 3's `liblouis.h`, which have not
//! changed since liblouis 2.6 (`lou_version`, `lou_charSize`,
//! `lou_setLogLevel`, `lou_findTable`, `lou_translateString`); buffers are
//! sized and their lengths passed as the header says; strings passed in are
//! NUL-terminated `CString`s; the library handle outlives the symbols (both
//! live in [`Louis`], and the functions are copied out of their `Symbol`s
//! only while the `Library` is owned by the same value).

#![allow(unsafe_code)]

use std::ffi::{CStr, CString, c_char, c_int, c_uint, c_ushort, c_void};
use std::sync::Mutex;

use libloading::Library;

/// `lou_translateString`'s modes: output as dot patterns in Unicode braille,
/// characters the table does not define left out (they are found separately).
const DOTS_IO: c_int = 4;
const UC_BRL: c_int = 64;
const NO_UNDEFINED: c_int = 128;
/// `LOU_LOG_OFF`: liblouis says nothing on stderr (taxel reports instead).
const LOG_OFF: c_int = 60000;

type VersionFn = unsafe extern "C" fn() -> *const c_char;
type CharSizeFn = unsafe extern "C" fn() -> c_int;
type LogLevelFn = unsafe extern "C" fn(c_int);
type FindTableFn = unsafe extern "C" fn(*const c_char) -> *mut c_char;
type TranslateFn = unsafe extern "C" fn(
    *const c_char,
    *const c_void,
    *mut c_int,
    *mut c_void,
    *mut c_int,
    *mut c_ushort,
    *mut c_char,
    c_int,
) -> c_int;

/// One lock for every call into liblouis, process-wide: its state (the
/// table cache, the table index) is global, shared by every [`Louis`] the
/// process opens (the system's loader gives them one library).
static LOCK: Mutex<()> = Mutex::new(());

/// The names the library is looked for under, in order, when no name is given.
pub const LIBRARY_NAMES: &[&str] =
    &["liblouis.so.20", "liblouis.so", "liblouis.20.dylib", "liblouis.dylib", "liblouis-20.dll", "liblouis.dll"];

/// An opened liblouis.
pub struct Louis {
    version: String,
    /// Bytes of liblouis's `widechar`: 2 or 4.
    char_size: usize,
    find_table: FindTableFn,
    translate: TranslateFn,
    // Kept last: dropped after the function pointers above are no longer usable.
    _lib: Library,
}

impl std::fmt::Debug for Louis {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Louis").field("version", &self.version).finish()
    }
}

impl Louis {
    /// Opens liblouis under `name` (a file name the system's loader
    /// searches for, or a path), or the first of [`LIBRARY_NAMES`] that
    /// opens. The error says what was tried.
    pub fn open(name: Option<&str>) -> Result<Louis, String> {
        let names: Vec<&str> = match name {
            Some(n) => vec![n],
            None => LIBRARY_NAMES.to_vec(),
        };
        let mut last = String::new();
        for n in &names {
            // SAFETY: loading a library runs its initialisers; liblouis's
            // do nothing but set up its own static state.
            match unsafe { Library::new(*n) } {
                Ok(lib) => return Self::from_library(lib).map_err(|e| format!("{n}: {e}")),
                Err(e) => last = e.to_string(),
            }
        }
        Err(format!("liblouis was not found (tried {}; {last})", names.join(", ")))
    }

    fn from_library(lib: Library) -> Result<Louis, String> {
        // SAFETY: see the module's documentation; the types are those of liblouis.h.
        unsafe {
            let version: VersionFn = *lib.get::<VersionFn>(b"lou_version\0").map_err(|e| e.to_string())?;
            let char_size: CharSizeFn = *lib.get::<CharSizeFn>(b"lou_charSize\0").map_err(|e| e.to_string())?;
            let log_level: LogLevelFn = *lib.get::<LogLevelFn>(b"lou_setLogLevel\0").map_err(|e| e.to_string())?;
            let find_table: FindTableFn = *lib.get::<FindTableFn>(b"lou_findTable\0").map_err(|e| e.to_string())?;
            let translate: TranslateFn =
                *lib.get::<TranslateFn>(b"lou_translateString\0").map_err(|e| e.to_string())?;
            let v = version();
            let version = if v.is_null() { String::new() } else { CStr::from_ptr(v).to_string_lossy().into_owned() };
            let char_size = match char_size() {
                2 => 2,
                4 => 4,
                n => return Err(format!("liblouis {version} has {n}-byte characters, expected 2 or 4")),
            };
            log_level(LOG_OFF);
            Ok(Louis { version, char_size, find_table, translate, _lib: lib })
        }
    }

    /// liblouis's version (`lou_version`), such as `3.24.0`.
    pub fn version(&self) -> &str {
        &self.version
    }

    /// The best table for a metadata query (`lou_findTable`), such as
    /// `language:fr type:literary contraction:full`; `None` when none matches.
    pub fn find_table(&self, query: &str) -> Option<String> {
        let q = CString::new(query).ok()?;
        let _guard = LOCK.lock().unwrap_or_else(|p| p.into_inner());
        // SAFETY: `q` is NUL-terminated; the result is NULL or a C string
        // that the caller owns. It is copied and, as it was allocated with
        // the C library's `malloc` that Rust cannot free portably, left
        // allocated: a few bytes per distinct query, and the caller caches
        // the answer per language.
        unsafe {
            let p = (self.find_table)(q.as_ptr());
            if p.is_null() { None } else { Some(CStr::from_ptr(p).to_string_lossy().into_owned()) }
        }
    }

    /// `text` in braille through `table` (a table list as liblouis takes
    /// it), cells as 8-dot masks (bit `k` is dot `k + 1`); characters the
    /// table does not define are left out. `None` when the table cannot
    /// be compiled (a missing file, an error in it).
    pub fn translate(&self, table: &str, text: &str) -> Option<Vec<u8>> {
        let table = CString::new(table).ok()?;
        let input = encode(text, self.char_size);
        let in_chars = input.len() / self.char_size;
        if in_chars == 0 {
            return Some(Vec::new());
        }
        let in_len = c_int::try_from(in_chars).ok()?;
        // Contractions shorten text; numbers, capitals and signs lengthen
        // it, by at most a few cells a character. Grown and tried again if
        // liblouis stopped short of the input's end.
        let mut capacity = 4 * in_chars + 16;
        for _ in 0..4 {
            let mut out = vec![0u8; capacity * self.char_size];
            let (mut inl, mut outl) = (in_len, c_int::try_from(capacity).ok()?);
            let _guard = LOCK.lock().unwrap_or_else(|p| p.into_inner());
            // SAFETY: `input` holds `in_len` widechars; `out` has room for
            // `outl` widechars; typeform and spacing may be NULL.
            let ok = unsafe {
                (self.translate)(
                    table.as_ptr(),
                    input.as_ptr().cast(),
                    &mut inl,
                    out.as_mut_ptr().cast(),
                    &mut outl,
                    std::ptr::null_mut(),
                    std::ptr::null_mut(),
                    DOTS_IO | UC_BRL | NO_UNDEFINED,
                )
            };
            drop(_guard);
            if ok == 0 {
                return None;
            }
            if inl >= in_len || (outl as usize) < capacity {
                let n = (outl.max(0) as usize).min(capacity);
                return Some(decode(&out[..n * self.char_size], self.char_size));
            }
            capacity *= 4;
        }
        None
    }
}

/// Text as liblouis's `widechar`s (UTF-16 or UTF-32, native byte order).
fn encode(text: &str, char_size: usize) -> Vec<u8> {
    if char_size == 2 {
        text.encode_utf16().flat_map(|u| (u as c_ushort).to_ne_bytes()).collect()
    } else {
        text.chars().flat_map(|c| (c as c_uint).to_ne_bytes()).collect()
    }
}

/// Output widechars to 8-dot cells: Unicode braille (U+2800 + mask) or,
/// should a table write them, liblouis's dot codes (0x8000 + mask);
/// anything else (a space) is an empty cell.
fn decode(out: &[u8], char_size: usize) -> Vec<u8> {
    out.chunks_exact(char_size)
        .map(|b| {
            let v = if char_size == 2 {
                u16::from_ne_bytes([b[0], b[1]]) as u32
            } else {
                u32::from_ne_bytes([b[0], b[1], b[2], b[3]])
            };
            match v {
                0x2800..=0x28ff => (v - 0x2800) as u8,
                0x8000..=0xffff => (v & 0xff) as u8,
                _ => 0,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn widechars_round_trip_both_sizes() {
        for size in [2, 4] {
            let e = encode("a⠃", size);
            assert_eq!(e.len(), 2 * size);
            assert_eq!(decode(&e, size), [0, 0x03]);
        }
        // A character past the BMP is two UTF-16 units.
        assert_eq!(encode("𝄞", 2).len(), 4);
    }

    #[test]
    fn a_missing_library_is_an_error_naming_what_was_tried() {
        let e = Louis::open(Some("liblouis-taxel-test-missing.so.99")).unwrap_err();
        assert!(e.contains("liblouis-taxel-test-missing.so.99"), "{e}");
    }
}
