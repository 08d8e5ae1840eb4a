//! Writes scenes/skies/stylized.exr: `environment::stylized_sky::bake` as 16-bit EXR (ZIP).
//! `cargo run --release --example bake_stylized_sky`; the shipped file is this output.

use shadematrix::environment::stylized_sky::{bake, HEIGHT, WIDTH};

fn main() {
    let rgba: Vec<f32> = bake(WIDTH, HEIGHT).iter().flat_map(|c| [c[0], c[1], c[2], 1.0]).collect();
    let bytes = shadematrix::images::encode::exr_half_bytes_with(
        WIDTH as u32,
        HEIGHT as u32,
        &rgba,
        exr::compression::Compression::ZIP16,
    )
    .expect("encoding the sky");
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/skies/stylized.exr");
    std::fs::write(&path, bytes).expect("writing the sky");
    println!("wrote {}", path.display());
}
