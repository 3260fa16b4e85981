//! The C ABI the page calls (see the crate's documentation for the calls).
//! Every function takes and returns numbers; buffers are addresses in the
//! module's linear memory, valid until the next call.
//!
//! `unsafe_code` is allowed in this module only because exporting a function
//! under its own name needs `#[unsafe(no_mangle)]`; nothing here dereferences
//! a raw pointer or calls unsafe code (addresses are only handed out).
#![allow(unsafe_code)]

use std::cell::RefCell;

use crate::{Session, tick_of};

/// What the module holds between calls.
#[derive(Default)]
struct State {
    /// Where the page writes the bundle before `taxel_load`.
    input: Vec<u8>,
    /// The bundle being played (its bytes live as long as the instance).
    session: Option<Session<'static>>,
    /// Text handed to the page: a name, an error message, the info JSON.
    text: String,
}

thread_local! {
    static STATE: RefCell<State> = RefCell::new(State::default());
}

fn with<R>(f: impl FnOnce(&mut State) -> R) -> R {
    STATE.with(|s| f(&mut s.borrow_mut()))
}

/// Sets the text buffer and returns its length in bytes.
fn set_text(st: &mut State, text: &str) -> usize {
    st.text.clear();
    st.text.push_str(text);
    st.text.len()
}

/// Room for a bundle of `len` bytes (zeroed); returns its address.
#[unsafe(no_mangle)]
pub extern "C" fn taxel_input(len: usize) -> usize {
    with(|st| {
        st.input = vec![0; len];
        st.input.as_ptr() as usize
    })
}

/// Loads the bundle written at `taxel_input`'s address: 0 when it plays, 1
/// when not (the reason is in the text buffer, `taxel_text_len` bytes).
#[unsafe(no_mangle)]
pub extern "C" fn taxel_load() -> u32 {
    with(|st| {
        // The bytes must outlive the player that reads them in place: they
        // live as long as the instance (one instance per bundle).
        // A stored (compressed) bundle is inflated once, here.
        let input = std::mem::take(&mut st.input);
        let plain = match taxel_format::stored::plain(&input) {
            Ok(p) => p.into_owned(),
            Err(e) => {
                st.session = None;
                set_text(st, &format!("not a valid taxel bundle: {e}"));
                return 1;
            }
        };
        let bytes: &'static [u8] = plain.leak();
        match Session::load(bytes) {
            Ok(s) => {
                st.session = Some(s);
                set_text(st, "");
                0
            }
            Err(e) => {
                st.session = None;
                set_text(st, &e);
                1
            }
        }
    })
}

/// The address of the text buffer.
#[unsafe(no_mangle)]
pub extern "C" fn taxel_text_ptr() -> usize {
    with(|st| st.text.as_ptr() as usize)
}

/// The length of the text buffer in bytes.
#[unsafe(no_mangle)]
pub extern "C" fn taxel_text_len() -> usize {
    with(|st| st.text.len())
}

/// The bundle's profile and shape as JSON in the text buffer; returns its length (0 before a load).
#[unsafe(no_mangle)]
pub extern "C" fn taxel_info() -> usize {
    with(|st| {
        let info = st.session.as_ref().map(Session::info).unwrap_or_default();
        set_text(st, &info)
    })
}

/// The latero frame's address (one `u16` per actuator), 0 for another family.
#[unsafe(no_mangle)]
pub extern "C" fn taxel_latero_frame(tick: f64, x: f32, y: f32) -> usize {
    with(|st| match st.session.as_mut() {
        Some(s) => address(s.latero_frame(tick_of(tick), x, y)),
        None => 0,
    })
}

/// The pin frame's address (one byte per pin), 0 for another family.
#[unsafe(no_mangle)]
pub extern "C" fn taxel_pins_frame(tick: f64, x: f32, y: f32) -> usize {
    with(|st| match st.session.as_mut() {
        Some(s) => address(s.pins_frame(tick_of(tick), x, y)),
        None => 0,
    })
}

/// The last pin frame's viewport: `col + row · 65536`.
#[unsafe(no_mangle)]
pub extern "C" fn taxel_pins_view() -> u32 {
    with(|st| {
        st.session.as_ref().map_or(0, |s| {
            let (c, r) = s.pins_viewport();
            c.min(0xffff) | (r.min(0xffff) << 16)
        })
    })
}

/// The finger sample's address (six `f32`), 0 for another family.
#[unsafe(no_mangle)]
pub extern "C" fn taxel_finger_sample(tick: f64, x: f32, y: f32, contact: u32) -> usize {
    with(|st| match st.session.as_mut() {
        Some(s) => address(s.finger_sample(tick_of(tick), x, y, contact != 0)),
        None => 0,
    })
}

/// The grid frame's address (one `f32` amplitude per actuator), 0 for another family.
#[unsafe(no_mangle)]
pub extern "C" fn taxel_grid_frame(tick: f64) -> usize {
    with(|st| match st.session.as_mut() {
        Some(s) => address(s.grid_frame(tick_of(tick))),
        None => 0,
    })
}

/// The name of the element under `(x, y)` mm in the text buffer; returns its length, 0 for none.
#[unsafe(no_mangle)]
pub extern "C" fn taxel_name_at(x: f64, y: f64) -> usize {
    with(|st| {
        let name = st.session.as_ref().and_then(|s| s.name_at(x, y)).unwrap_or_default();
        set_text(st, &name)
    })
}

/// The id of the element under `(x, y)` mm in the text buffer; returns its length, 0 for none.
#[unsafe(no_mangle)]
pub extern "C" fn taxel_id_at(x: f64, y: f64) -> usize {
    with(|st| {
        let id = st.session.as_ref().and_then(|s| s.id_at(x, y)).unwrap_or_default();
        set_text(st, &id)
    })
}

/// A frame's address, 0 when the family has no such frame.
fn address<T>(frame: &[T]) -> usize {
    if frame.is_empty() { 0 } else { frame.as_ptr() as usize }
}
