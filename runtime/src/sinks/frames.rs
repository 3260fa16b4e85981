//! Frames as CSV: a header `tick,a0,a1,…` and one line per tick with each
//! actuator's output code (index `cols · row + col`), or its level in 0..=1
//! for a grid.
//!
//! ```
//! use taxel_format::Tick;
//! use taxel_runtime::sinks::frames::FramesCsv;
//!
//! let mut csv = FramesCsv::new(Vec::new(), 3).unwrap();
//! csv.frame(Tick(7), &[0, 512, 1023]).unwrap();
//! let text = String::from_utf8(csv.finish().unwrap()).unwrap();
//! assert_eq!(text, "tick,a0,a1,a2\n7,0,512,1023\n");
//! ```

use std::io::{self, Write};
use std::vec::Vec;

use taxel_format::Tick;

/// Writes frames of integer codes as CSV to any writer (buffer it yourself
/// for files; lines are formatted into one reused buffer).
#[derive(Debug)]
pub struct FramesCsv<W: Write> {
    out: W,
    actuators: usize,
    line: Vec<u8>,
}

impl<W: Write> FramesCsv<W> {
    /// Writes the header for `actuators` actuators.
    pub fn new(mut out: W, actuators: usize) -> io::Result<Self> {
        let mut line = Vec::with_capacity(8 * actuators + 24);
        line.extend_from_slice(b"tick");
        for a in 0..actuators {
            line.extend_from_slice(b",a");
            push_u64(&mut line, a as u64);
        }
        line.push(b'\n');
        out.write_all(&line)?;
        Ok(FramesCsv { out, actuators, line })
    }

    /// Writes one frame: the tick and the first `actuators` codes (missing
    /// codes are written as 0, so every line has the header's columns).
    pub fn frame(&mut self, tick: Tick, codes: &[u16]) -> io::Result<()> {
        self.line.clear();
        push_u64(&mut self.line, tick.0);
        for a in 0..self.actuators {
            self.line.push(b',');
            push_u64(&mut self.line, codes.get(a).copied().unwrap_or(0) as u64);
        }
        self.line.push(b'\n');
        self.out.write_all(&self.line)
    }

    /// Writes one frame of levels in 0..=1 (a grid's amplitudes), each with
    /// six decimals: the tick and the first `actuators` levels (missing ones
    /// are written as 0).
    pub fn levels(&mut self, tick: Tick, levels: &[f32]) -> io::Result<()> {
        self.line.clear();
        push_u64(&mut self.line, tick.0);
        for a in 0..self.actuators {
            // Writing into a Vec cannot fail.
            let _ = write!(self.line, ",{:.6}", levels.get(a).copied().unwrap_or(0.0));
        }
        self.line.push(b'\n');
        self.out.write_all(&self.line)
    }

    /// Flushes and returns the writer.
    pub fn finish(mut self) -> io::Result<W> {
        self.out.flush()?;
        Ok(self.out)
    }
}

/// Appends the decimal digits of `v` (without `fmt`, which is slower per number).
fn push_u64(buf: &mut Vec<u8>, mut v: u64) {
    let mut digits = [0u8; 20];
    let mut i = digits.len();
    loop {
        i -= 1;
        digits[i] = b'0' + (v % 10) as u8;
        v /= 10;
        if v == 0 {
            break;
        }
    }
    buf.extend_from_slice(&digits[i..]);
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::string::String;

    #[test]
    fn numbers_are_written_in_decimal() {
        let mut csv = FramesCsv::new(Vec::new(), 2).unwrap();
        csv.frame(Tick(u64::MAX), &[65535, 0]).unwrap();
        csv.frame(Tick(10), &[9]).unwrap();
        let text = String::from_utf8(csv.finish().unwrap()).unwrap();
        assert_eq!(text, "tick,a0,a1\n18446744073709551615,65535,0\n10,9,0\n");
    }

    #[test]
    fn levels_have_six_decimals() {
        let mut csv = FramesCsv::new(Vec::new(), 3).unwrap();
        csv.levels(Tick(2), &[0.5, 1.0]).unwrap();
        let text = String::from_utf8(csv.finish().unwrap()).unwrap();
        assert_eq!(text, "tick,a0,a1,a2\n2,0.500000,1.000000,0.000000\n");
    }
}
