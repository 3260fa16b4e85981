//! Frames drawn as text, to be read by a person: `.` rest, `#` full
//! deflection, a digit d for δ in [d/10, (d+1)/10). Row 0 (the top of the
//! array, smallest page y) is the first line.
//!
//! The wavelengths are six actuator pitches, so one period shows
//! δ = 1, ¾, ¼, 0, ¼, ¾ (`#72.27`).

use crate::support::*;

#[test]
fn vertical_grating() {
    // θ = 90°: ridges run along y, so every row is the same. λ = 6 x 1.2 mm;
    // column 0 sits at x = 21.6 mm = 3λ, on a ridge.
    let p = stress2();
    let bytes = bundle_bytes(p, vec![full_surface(grating(7.2, 90.0), 1.0)]);
    let frame = play(&bytes, 0, 21.6 + 4.2, 30.0);
    assert_eq!(
        art(&p, &frame),
        "\
#72.27#7
#72.27#7
#72.27#7
#72.27#7
#72.27#7
#72.27#7
#72.27#7
#72.27#7
"
    );
}

#[test]
fn horizontal_grating() {
    // θ = 0°: ridges run along x, so every column is the same. λ = 6 x 1.4 mm;
    // row 0 sits at y = 16.8 mm = 2λ, on a ridge.
    let p = stress2();
    let bytes = bundle_bytes(p, vec![full_surface(grating(8.4, 0.0), 1.0)]);
    let frame = play(&bytes, 0, 50.0, 16.8 + 4.9);
    assert_eq!(
        art(&p, &frame),
        "\
########
77777777
22222222
........
22222222
77777777
########
77777777
"
    );
}

#[test]
fn grating_at_45_degrees_rises_from_bottom_left_to_top_right() {
    // On a square 1 mm pitch, with the author's angle measured on the page
    // (y down), ridges at +45° run like `/`: the `#` of row 4 column 0 and
    // row 0 column 4 lie on one ridge. λ = 6/√2 mm puts six diagonal steps in a period.
    let p = square_profile();
    let bytes = bundle_bytes(p, vec![full_surface(grating(6.0 / 2f32.sqrt(), 45.0), 1.0)]);
    let frame = play(&bytes, 0, 18.0 + 3.5, 18.0 + 3.5);
    assert_eq!(
        art(&p, &frame),
        "\
#72.27#7
72.27#72
2.27#72.
.27#72.2
27#72.27
7#72.27#
#72.27#7
72.27#72
"
    );
}

#[test]
fn grating_at_minus_45_degrees_falls_from_top_left_to_bottom_right() {
    let p = square_profile();
    let bytes = bundle_bytes(p, vec![full_surface(grating(6.0 / 2f32.sqrt(), -45.0), 1.0)]);
    let frame = play(&bytes, 0, 18.0 + 3.5, 18.0 + 3.5);
    assert_eq!(
        art(&p, &frame),
        "\
#72.27#7
7#72.27#
27#72.27
.27#72.2
2.27#72.
72.27#72
#72.27#7
7#72.27#
"
    );
}

#[test]
fn one_dot() {
    // A dot of radius 4 mm centred on actuator (row 4, column 4): the plateau
    // (r ≤ 1 mm) holds only that actuator; columns are 1.2 mm apart and rows
    // 1.4 mm, so the dot spreads further along a row than down a column.
    let p = stress2();
    let bytes = bundle_bytes(p, vec![dots(&[(50.6, 30.7, 4.0, 1.0)])]);
    let frame = play(&bytes, 0, 50.0, 30.0);
    assert_eq!(
        art(&p, &frame),
        "\
........
........
..02320.
.0389830
.059#950
.0389830
..02320.
........
"
    );
}
