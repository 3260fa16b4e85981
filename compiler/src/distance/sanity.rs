//! The invariants of a distance layer as the writer makes it, beyond what
//! the format's validating reader checks (spade's `sanity_check`): the tests
//! call [`sanity_check`] on the layers they build, so a writer change that
//! breaks one fails there, naming the tile.
//!
//! What holds, and why:
//! - **The lattice.** The origin sits on a multiple of the pitch from the
//!   page origin (`build_field`: every layer of a drawing samples the same
//!   points), and the pitch and step are positive.
//! - **Stored tiles are crossed by the ramp.** A tile whose samples all
//!   play full amplitude is the entry "inside", all zero "outside" (SPEC.md
//!   section 6.2); a stored tile has a sample that plays neither.
//! - **1-Lipschitz samples.** A stored sample is the signed distance in
//!   steps, clamped and rounded; the distance changes by at most one pitch
//!   between neighbouring lattice points, so neighbouring codes differ by at
//!   most `pitch / step` plus one (the two roundings).
//! - **Saturated tiles meet no edge.** An inside tile and an outside tile
//!   share the samples of their common side, which cannot be both full and
//!   zero: they are never side by side. A stored tile beside an inside
//!   (outside) tile has the same samples on their common side, so they play
//!   full (zero) amplitude there too.
//!
//! Not an invariant: an analytic tile's gradient. The writer fits a plane
//! to the tile's codes by least squares and keeps it where it is within
//! half a code of the exact distance near the edge and saturated on the
//! right side elsewhere (`planes.rs`), so a plane across a curved edge may
//! be steeper than a distance (the exp5 circle icons have one of 63.7 codes
//! a cell where the distance has 63.0); checking it needs the geometry,
//! which the writer's own check and the property tests against exact f64
//! geometry have.

use taxel_format::{
    DISTANCE_ZERO, DistanceLayer, TILE_CELLS, TILE_INSIDE, TILE_OUTSIDE, TILE_SAMPLES, TILE_SIDE, TileEntry, edge_ramp,
};

use super::{Field, FieldParams};

/// The parts of a layer the invariants are about, from a bundle's layer
/// or from the writer's [`Field`].
struct Tiles<'a> {
    origin: (f64, f64),
    pitch_mm: f64,
    step_mm: f64,
    soft_mm: f64,
    tile_cols: u32,
    tile_rows: u32,
    tiles: &'a [u32],
    samples: &'a [u8],
}

/// Checks the invariants above on `layer`; the error names the first tile
/// (column, row) that breaks one, and how.
pub fn sanity_check(layer: &DistanceLayer) -> Result<(), String> {
    check(&Tiles {
        origin: (layer.origin_x.0 as f64, layer.origin_y.0 as f64),
        pitch_mm: layer.pitch_mm as f64,
        step_mm: layer.step_mm as f64,
        soft_mm: layer.soft_mm as f64,
        tile_cols: layer.tile_cols,
        tile_rows: layer.tile_rows,
        tiles: &layer.tiles,
        samples: &layer.samples,
    })
}

impl Field {
    /// [`sanity_check`] on a field built with `params`, before it becomes a layer.
    pub fn sanity_check(&self, params: FieldParams) -> Result<(), String> {
        check(&Tiles {
            origin: self.origin,
            pitch_mm: params.pitch_mm,
            step_mm: self.step_mm,
            soft_mm: params.soft_mm,
            tile_cols: self.tile_cols,
            tile_rows: self.tile_rows,
            tiles: &self.tiles,
            samples: &self.samples,
        })
    }
}

/// The lowest code that plays full amplitude and the highest that plays
/// zero under the layer's edge profile, with the writer's margin of a
/// hundredth of a code (`saturated_codes`, which decides the inside and
/// outside tiles).
fn saturation(layer: &Tiles<'_>) -> (f32, f32) {
    let step = layer.step_mm as f32;
    let half = 0.5 * edge_ramp(layer.soft_mm as f32, step) / step;
    let zero = DISTANCE_ZERO as f32;
    ((zero + half + 0.01).ceil().clamp(zero + 1.0, 255.0), (zero - half - 0.01).floor().clamp(0.0, zero - 1.0))
}

fn check(layer: &Tiles<'_>) -> Result<(), String> {
    let (h, step) = (layer.pitch_mm, layer.step_mm);
    if !(h > 0.0 && step > 0.0 && h.is_finite() && step.is_finite()) {
        return Err(format!("pitch {h} mm and step {step} mm must be positive"));
    }
    for (axis, o) in [("x", layer.origin.0), ("y", layer.origin.1)] {
        // The origin went through f32: a relative 1e-6 of it, in pitches.
        let off = o / h - (o / h).round();
        if off.abs() > 1e-3 + 1e-6 * (o / h).abs() {
            return Err(format!("origin {axis} {o} mm is not on a multiple of the {h} mm pitch"));
        }
    }
    let (cols, rows) = (layer.tile_cols as usize, layer.tile_rows as usize);
    if layer.tiles.len() != cols * rows {
        return Err(format!("{} index entries for {cols} x {rows} tiles", layer.tiles.len()));
    }
    let (full, none) = saturation(layer);
    // Codes between neighbouring lattice points: one pitch, plus the roundings.
    let lipschitz = (h / step) as f32 + 1.0 + 1e-3;
    for r in 0..rows {
        for c in 0..cols {
            let e = TileEntry::of(layer.tiles[r * cols + c]);
            let at = |what: String| Err(format!("tile ({c}, {r}), {e:?}: {what}"));
            if let TileEntry::Stored(k) = e {
                let Some(s) = layer.samples.get(k as usize * TILE_SAMPLES..(k as usize + 1) * TILE_SAMPLES) else {
                    return at("its samples are missing".into());
                };
                let code = |i: usize, j: usize| s[j * TILE_SIDE + i] as f32;
                if s.iter().all(|&v| v as f32 >= full) || s.iter().all(|&v| v as f32 <= none) {
                    return at("every sample saturates the profile: the tile should be inside or outside".into());
                }
                for j in 0..TILE_SIDE {
                    for i in 0..TILE_SIDE {
                        for (ni, nj) in [(i + 1, j), (i, j + 1)] {
                            if ni < TILE_SIDE && nj < TILE_SIDE && (code(i, j) - code(ni, nj)).abs() > lipschitz {
                                return at(format!(
                                    "samples ({i}, {j}) and ({ni}, {nj}) differ by more than {lipschitz} codes: {} and {}",
                                    code(i, j),
                                    code(ni, nj)
                                ));
                            }
                        }
                    }
                }
                // The sides shared with a saturated neighbour (left, right, top, bottom).
                let sides = [
                    (c.checked_sub(1).map(|c| (c, r)), [0, 0], [0, 1]),
                    ((c + 1 < cols).then_some((c + 1, r)), [TILE_CELLS, 0], [0, 1]),
                    (r.checked_sub(1).map(|r| (c, r)), [0, 0], [1, 0]),
                    ((r + 1 < rows).then_some((c, r + 1)), [0, TILE_CELLS], [1, 0]),
                ];
                for (n, start, dir) in sides {
                    let Some((nc, nr)) = n else { continue };
                    let want: fn(f32, f32, f32) -> bool = match layer.tiles[nr * cols + nc] {
                        TILE_INSIDE => |v, full, _| v >= full,
                        TILE_OUTSIDE => |v, _, none| v <= none,
                        _ => continue,
                    };
                    for k in 0..TILE_SIDE {
                        let (i, j) = (start[0] + k * dir[0], start[1] + k * dir[1]);
                        if !want(code(i, j), full, none) {
                            return at(format!(
                                "sample ({i}, {j}) is {} beside the saturated tile ({nc}, {nr})",
                                code(i, j)
                            ));
                        }
                    }
                }
            }
            // (Each pair once: the inside tile looks right and down, and an
            // outside one too, for an inside tile right of or below it.)
            let here = layer.tiles[r * cols + c];
            if here == TILE_INSIDE || here == TILE_OUTSIDE {
                let other = if here == TILE_INSIDE { TILE_OUTSIDE } else { TILE_INSIDE };
                for (nc, nr) in [(c + 1, r), (c, r + 1)] {
                    if nc < cols && nr < rows && layer.tiles[nr * cols + nc] == other {
                        return at(format!("a tile of the other saturation ({nc}, {nr}) beside it"));
                    }
                }
            }
        }
    }
    Ok(())
}
