fn main() {
    let g = shadematrix::gpu::GpuContext::new().unwrap();
    println!(
        "{} features {:?}",
        g.record.name,
        g.adapter.features().contains(wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES)
    );
    for f in [
        wgpu::TextureFormat::Rgba32Float,
        wgpu::TextureFormat::Rgba16Float,
        wgpu::TextureFormat::R8Uint,
        wgpu::TextureFormat::Depth32Float,
    ] {
        let ff = g.adapter.get_texture_format_features(f);
        println!("{f:?}: {:?}", ff.flags);
    }
}
