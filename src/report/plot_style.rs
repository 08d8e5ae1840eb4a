//! What the SVG plots share (error against run time, conditioning, convergence): the palette
//! (matplotlib's tab10) and how a plotters failure is reported.

use plotters::style::RGBColor;

use crate::error::Error;

pub const PALETTE: [RGBColor; 10] = [
    RGBColor(0x1f, 0x77, 0xb4),
    RGBColor(0xff, 0x7f, 0x0e),
    RGBColor(0x2c, 0xa0, 0x2c),
    RGBColor(0xd6, 0x27, 0x28),
    RGBColor(0x94, 0x67, 0xbd),
    RGBColor(0x8c, 0x56, 0x4b),
    RGBColor(0xe3, 0x77, 0xc2),
    RGBColor(0x7f, 0x7f, 0x7f),
    RGBColor(0xbc, 0xbd, 0x22),
    RGBColor(0x17, 0xbe, 0xcf),
];

/// A drawing error of the plot `what`.
pub fn failed(what: &str, e: &dyn std::fmt::Display) -> Error {
    Error::Other(format!("drawing {what}: {e}"))
}
