//! A coded tile's 64 codes (format 4.6, SPEC.md section 9.1): each code
//! predicted from the codes before it in the tile, and the residuals stored
//! in three arrays of fixed widths: the tile's two slopes (nodes 1 and 8,
//! less node 0), the rest of its first row and column, and the inside.
//!
//! The prediction is the plane through the neighbours: inside the tile
//! `W + N − NW` (exact on a plane, and on the facets of a triangle mesh,
//! whose heights the compiler samples), along the first row and column the
//! line through the two nodes before (`2 W − WW`, `2 N − NN`). The slopes
//! have a width of their own because they are large on any incline while
//! the other residuals are the surface's bending: in one width they took
//! 9 or 10 bits for every node of the first row and column of the paper's
//! convex shape, whose second differences need 5. A tile is decoded on its
//! own, so a player reads one tile for a cell and never a chain of them.
//!
//! A residual `r` of width `w` is stored as `r + 2^(w−1)` (offset binary:
//! the same range as a zigzag code of `w` bits, and one subtraction to
//! read). Each array has fixed-width entries, so every residual's place is
//! known without reading the ones before it: a player reads a row's seven
//! inside residuals from one 64-bit load. All arithmetic is on `i32`
//! modulo 2³², so a residual of up to 32 bits reaches any code and a
//! hostile record cannot overflow.

use alloc::vec::Vec;

use super::word;

/// Nodes in a tile.
pub(crate) const NODES: usize = 64;
/// Bits of each of the three widths at the start of the residual stream.
const WIDTH_BITS: u32 = 6;
/// Largest residual width.
pub(crate) const MAX_WIDTH: u32 = 32;
/// Largest residual stream, in words (three widths, 63 residuals of 32 bits).
const MAX_STREAM_WORDS: usize = (3 * WIDTH_BITS as usize + 63 * 32).div_ceil(32);
/// The bytes a decoder reads a stream from: the longest stream and 8 more,
/// so a 64-bit load at any bit of it stays inside.
const STREAM_BYTES: usize = 4 * MAX_STREAM_WORDS + 8;

/// The nodes of each array, in the order they are stored: the slopes, the
/// first row and then the first column, the inside row by row.
const SLOPES: [usize; 2] = [1, 8];
const BORDER: [usize; 12] = [2, 3, 4, 5, 6, 7, 16, 24, 32, 40, 48, 56];

/// Bits of a residual stream with widths `w` (slopes, border, inside).
#[inline]
pub(crate) fn stream_bits(w: [u32; 3]) -> u32 {
    3 * WIDTH_BITS + 2 * w[0] + 12 * w[1] + 49 * w[2]
}

/// Words of a residual stream with widths `w`.
#[inline]
pub(crate) fn stream_words(w: [u32; 3]) -> u32 {
    stream_bits(w).div_ceil(32)
}

/// The widths (slopes, border, inside) of the stream at word `at` of the pool.
#[inline]
pub(crate) fn widths(pool: &[u8], at: u32) -> [u32; 3] {
    let w = word(pool, at);
    [0, 1, 2].map(|g| (w >> (g * WIDTH_BITS)) & 0x3f)
}

/// A residual stream: the pool from the stream's first byte on, or, for a
/// record near the pool's end, a copy padded with zeros (past the pool's
/// end a stream reads zeros). Either way a fixed-size array, so the
/// compiler drops the bounds checks of its reads.
// The copy is one decoding's stack buffer, made only near the pool's end;
// boxing it would allocate, which a player must not.
#[allow(clippy::large_enum_variant)]
enum Stream<'a> {
    InPlace(&'a [u8; STREAM_BYTES]),
    Copied([u8; STREAM_BYTES]),
}

impl Stream<'_> {
    /// The stream at word `at` of the pool, for widths `w` (at most 32 each).
    #[inline]
    fn of(pool: &[u8], at: u32, w: [u32; 3]) -> Stream<'_> {
        let start = (at as usize).saturating_mul(4).min(pool.len());
        if let Some(bytes) = pool[start..].first_chunk::<STREAM_BYTES>() {
            return Stream::InPlace(bytes);
        }
        let mut bytes = [0u8; STREAM_BYTES];
        let len = 4 * stream_words(w) as usize;
        let src = &pool[start..pool.len().min(start.saturating_add(len))];
        bytes[..src.len()].copy_from_slice(src);
        Stream::Copied(bytes)
    }

    /// The 64 bits from bit `p` on (at least 57 of them the stream's, or past it).
    #[inline(always)]
    fn window(&self, p: u32) -> u64 {
        let bytes = match self {
            Stream::InPlace(b) => *b,
            Stream::Copied(b) => b,
        };
        let o = ((p >> 3) as usize).min(STREAM_BYTES - 8);
        let b = bytes.get(o..).and_then(|b| b.first_chunk::<8>()).map_or(0, |b| u64::from_le_bytes(*b));
        b >> (p & 7)
    }

    /// `N` residuals of group `g` from bit `p` on: from one window when they
    /// fit in its 57 sure bits, else a window each.
    #[inline(always)]
    fn run<const N: usize>(&self, p: u32, g: Group) -> [i32; N] {
        let mut out = [0i32; N];
        if N as u32 * g.w <= 57 {
            // Each residual shifted out of the window on its own, not one
            // after the other: the shifts do not wait for each other.
            let bits = self.window(p);
            for (k, r) in out.iter_mut().enumerate() {
                *r = g.residual(bits >> (k as u32 * g.w));
            }
        } else {
            for (k, r) in out.iter_mut().enumerate() {
                *r = g.residual(self.window(p + k as u32 * g.w));
            }
        }
        out
    }
}

/// One array: its width, mask and offset.
#[derive(Clone, Copy)]
struct Group {
    w: u32,
    mask: u64,
    half: i32,
}

impl Group {
    fn of(w: u32) -> Self {
        let w = w.min(MAX_WIDTH);
        Group { w, mask: (1u64 << w) - 1, half: ((1u64 << w) >> 1) as u32 as i32 }
    }

    /// The residual held by the low bits of `bits`.
    #[inline(always)]
    fn residual(self, bits: u64) -> i32 {
        ((bits & self.mask) as u32 as i32).wrapping_sub(self.half)
    }
}

/// The stream's three arrays and where each starts.
struct Layout {
    groups: [Group; 3],
    starts: [u32; 3],
}

impl Layout {
    fn of(w: [u32; 3]) -> Self {
        let groups = w.map(Group::of);
        let s0 = 3 * WIDTH_BITS;
        let s1 = s0 + 2 * groups[0].w;
        Layout { groups, starts: [s0, s1, s1 + 12 * groups[1].w] }
    }
}

/// Decodes the codes of a tile whose node 0 has code `first` and whose
/// residual stream starts at word `at` of the pool. A width above 32 (which
/// a validated record never has) is read as 32.
#[inline]
pub(crate) fn decode(pool: &[u8], at: u32, first: u32, c: &mut [i32; NODES]) {
    let widths = widths(pool, at).map(|w| w.min(MAX_WIDTH));
    let s = Stream::of(pool, at, widths);
    let Layout { groups: [gs, gb, gi], starts: [ps, pb, pi] } = Layout::of(widths);
    let slopes: [i32; 2] = s.run(ps, gs);
    let row: [i32; 6] = s.run(pb, gb);
    let column: [i32; 6] = s.run(pb + 6 * gb.w, gb);
    c[0] = first as i32;
    // The first row and column along their lines, then the inside.
    c[1] = c[0].wrapping_add(slopes[0]);
    for a in 2..8 {
        c[a] = c[a - 1].wrapping_mul(2).wrapping_sub(c[a - 2]).wrapping_add(row[a - 2]);
    }
    c[8] = c[0].wrapping_add(slopes[1]);
    for b in 2..8 {
        c[8 * b] = c[8 * b - 8].wrapping_mul(2).wrapping_sub(c[8 * b - 16]).wrapping_add(column[b - 2]);
    }
    // The inside's residual width as a constant where it usually is, so
    // its shifts and masks are immediates (a tenth of a decoding's work).
    match gi.w {
        0 => inside::<0>(&s, pi, c),
        1 => inside::<1>(&s, pi, c),
        2 => inside::<2>(&s, pi, c),
        3 => inside::<3>(&s, pi, c),
        4 => inside::<4>(&s, pi, c),
        5 => inside::<5>(&s, pi, c),
        6 => inside::<6>(&s, pi, c),
        7 => inside::<7>(&s, pi, c),
        8 => inside::<8>(&s, pi, c),
        _ => inside_wide(&s, pi, gi, c),
    }
}

/// The inside of a tile from its first row and column, with residuals of
/// `W` bits (at most 8, so a row's seven come from one window) from bit
/// `p` on.
///
/// `W + N − NW` row by row is, for each column, the previous row's
/// difference to the west plus the residual: seven running differences,
/// then their sums along the row.
#[inline(always)]
fn inside<const W: u32>(s: &Stream<'_>, p: u32, c: &mut [i32; NODES]) {
    let g = Group::of(W);
    let mut d = [0i32; 8];
    for a in 1..8 {
        d[a] = c[a].wrapping_sub(c[a - 1]);
    }
    for b in 1..8 {
        let bits = s.window(p + (b as u32 - 1) * 7 * W);
        let mut west = c[8 * b];
        for a in 1..8 {
            d[a] = d[a].wrapping_add(g.residual(bits >> ((a as u32 - 1) * W)));
            west = west.wrapping_add(d[a]);
            c[8 * b + a] = west;
        }
    }
}

/// [`inside`] for residuals of any width (a window each).
fn inside_wide(s: &Stream<'_>, p: u32, g: Group, c: &mut [i32; NODES]) {
    let mut d = [0i32; 8];
    for a in 1..8 {
        d[a] = c[a].wrapping_sub(c[a - 1]);
    }
    for b in 1..8 {
        let row: [i32; 7] = s.run(p + (b as u32 - 1) * 7 * g.w, g);
        let mut west = c[8 * b];
        for a in 1..8 {
            d[a] = d[a].wrapping_add(row[a - 1]);
            west = west.wrapping_add(d[a]);
            c[8 * b + a] = west;
        }
    }
}

/// The nodes of the tile in the order of the stream's residuals.
fn stream_order() -> impl Iterator<Item = (usize, usize)> {
    let inside = (1..8).flat_map(|b| (1..8).map(move |a| 8 * b + a));
    SLOPES.into_iter().map(|l| (0, l)).chain(BORDER.into_iter().map(|l| (1, l))).chain(inside.map(|l| (2, l)))
}

/// The residuals of the tile's nodes as [`decode`] reads them (node 0's,
/// which is not stored, is 0), for the reader's check that nodes without
/// contact have residual 0.
pub(crate) fn residuals(pool: &[u8], at: u32) -> [i32; NODES] {
    let widths = widths(pool, at).map(|w| w.min(MAX_WIDTH));
    let s = Stream::of(pool, at, widths);
    let Layout { groups, starts } = Layout::of(widths);
    let mut out = [0i32; NODES];
    let mut p = starts[0];
    for (g, l) in stream_order() {
        out[l] = groups[g].residual(s.window(p));
        p += groups[g].w;
    }
    out
}

/// The prediction of node `l > 0` from the codes before it (in the order
/// [`decode`] computes them: each node's predictors come first).
fn predict(c: &[i32; NODES], l: usize) -> i32 {
    let (a, b) = (l % 8, l / 8);
    match (a, b) {
        (1, 0) | (0, 1) => c[0],
        (_, 0) => c[l - 1].wrapping_mul(2).wrapping_sub(c[l - 2]),
        (0, _) => c[l - 8].wrapping_mul(2).wrapping_sub(c[l - 16]),
        _ => c[l - 1].wrapping_add(c[l - 8]).wrapping_sub(c[l - 9]),
    }
}

/// The fewest bits that hold `r` in offset binary (`r + 2^(w−1)` in `w` bits).
fn width_of(r: i32) -> u32 {
    let magnitude = if r < 0 { !r } else { r } as u32;
    if r == 0 { 0 } else { 33 - magnitude.leading_zeros() }
}

/// Codes a tile: `codes[l]` for the nodes in `keep` (bit `l`), the others
/// predicted (residual 0). Returns node 0's code and the residual stream's
/// words. Node 0, when it is not kept, takes the code of the first node
/// that is (so the nodes after it are predicted from a code of the tile).
pub(crate) fn encode(codes: &[u32; NODES], keep: u64) -> (u32, Vec<u32>) {
    let kept = |l: usize| keep >> l & 1 != 0;
    let first = (0..NODES).find(|&l| kept(l)).map_or(0, |l| codes[l]);
    let mut c = [0i32; NODES];
    c[0] = first as i32;
    let mut r = [0i32; NODES];
    // Row-major order computes every node's predictors before it.
    for l in 1..NODES {
        let p = predict(&c, l);
        if kept(l) {
            c[l] = codes[l] as i32;
            r[l] = c[l].wrapping_sub(p);
        } else {
            c[l] = p;
        }
    }
    let mut w = [0u32; 3];
    for (g, l) in stream_order() {
        w[g] = w[g].max(width_of(r[l]));
    }
    let mut out = Vec::with_capacity(stream_words(w) as usize);
    let mut acc = 0u64;
    let mut have = 0u32;
    let mut put = |v: u32, w: u32, out: &mut Vec<u32>| {
        acc |= ((v as u64) & ((1u64 << w) - 1)) << have;
        have += w;
        if have >= 32 {
            out.push(acc as u32);
            acc >>= 32;
            have -= 32;
        }
    };
    for g in w {
        put(g, WIDTH_BITS, &mut out);
    }
    for (g, l) in stream_order() {
        let g = Group::of(w[g]);
        put(r[l].wrapping_add(g.half) as u32, g.w, &mut out);
    }
    if have > 0 {
        out.push(acc as u32);
    }
    debug_assert_eq!(out.len() as u32, stream_words(w));
    (first, out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bytes(words: &[u32]) -> Vec<u8> {
        words.iter().flat_map(|w| w.to_le_bytes()).collect()
    }

    #[test]
    fn widths_hold_the_residuals_in_offset_binary() {
        for (r, w) in
            [(0, 0), (-1, 1), (1, 2), (-2, 2), (2, 3), (-4, 3), (3, 3), (4, 4), (i32::MIN, 32), (i32::MAX, 32)]
        {
            assert_eq!(width_of(r), w, "{r}");
            let g = Group::of(w);
            assert_eq!(g.residual(r.wrapping_add(g.half) as u32 as u64), r, "{r}");
        }
    }

    #[test]
    fn the_stream_names_every_node_but_the_first_once() {
        let mut seen = [0; NODES];
        for (g, l) in stream_order() {
            seen[l] += 1;
            assert_eq!(
                g,
                if l == 1 || l == 8 {
                    0
                } else if l < 8 || l % 8 == 0 {
                    1
                } else {
                    2
                },
                "node {l}"
            );
        }
        assert_eq!(seen[0], 0);
        assert!(seen[1..].iter().all(|&n| n == 1));
    }

    #[test]
    fn a_plane_of_codes_needs_no_residual_bits_past_its_two_slopes() {
        let mut codes = [0u32; NODES];
        for (l, c) in codes.iter_mut().enumerate() {
            *c = 1000 + 7 * (l % 8) as u32 + 300 * (l / 8) as u32;
        }
        let (first, words) = encode(&codes, u64::MAX);
        assert_eq!(first, 1000);
        // The slopes (7 and 300 codes a node: 300 needs 10 bits) and nothing else.
        assert_eq!(widths(&bytes(&words), 0), [10, 0, 0]);
        let mut back = [0i32; NODES];
        decode(&bytes(&words), 0, first, &mut back);
        assert_eq!(back.map(|c| c as u32), codes);
    }

    #[test]
    fn codes_round_trip_through_every_width_and_hidden_nodes_predict() {
        let mut seed = 0x9e37_79b9u32;
        for case in 0..300 {
            let mut codes = [0u32; NODES];
            let span = 1u32 << (case % 25);
            for c in codes.iter_mut() {
                seed ^= seed << 13;
                seed ^= seed >> 17;
                seed ^= seed << 5;
                *c = seed % span.min(1 << 24);
            }
            let keep = if case % 3 == 0 { u64::MAX } else { (seed as u64) << 32 | seed.rotate_left(7) as u64 };
            let (first, words) = encode(&codes, keep);
            // The stream alone (read from a copy) and inside a longer pool (in place).
            let alone = bytes(&words);
            let mut long = alone.clone();
            long.resize(alone.len() + STREAM_BYTES, 0xa5);
            for pool in [&alone, &long] {
                let mut back = [0i32; NODES];
                decode(pool, 0, first, &mut back);
                let r = residuals(pool, 0);
                for l in 0..NODES {
                    if keep >> l & 1 != 0 {
                        assert_eq!(back[l] as u32, codes[l], "case {case}, node {l}");
                    } else if l > 0 {
                        assert_eq!(r[l], 0, "case {case}, hidden node {l}");
                    }
                }
            }
        }
    }
}
