//! Adapter selection and device creation, headless (no surface, no window).

use std::sync::{Arc, Mutex};

use super::constants::ConstantSpace;
pub use crate::adapter::AdapterRecord;
use crate::error::{Error, ADAPTER_HELP};

/// The constant space for `info`: gpu::constants' choice, or SHADEMATRIX_CONSTANTS=uniform|storage.
fn constant_space(info: &wgpu::AdapterInfo) -> Result<ConstantSpace, Error> {
    match std::env::var("SHADEMATRIX_CONSTANTS").ok().as_deref() {
        None | Some("") => Ok(ConstantSpace::for_adapter(info)),
        Some("uniform") => Ok(ConstantSpace::Uniform),
        Some("storage") => Ok(ConstantSpace::ReadOnlyStorage),
        Some(other) => Err(Error::Input(crate::input::names::unknown_name(
            "environment",
            "SHADEMATRIX_CONSTANTS",
            "constant space",
            other,
            &["uniform", "storage"],
        ))),
    }
}

pub struct GpuContext {
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub record: AdapterRecord,
    /// The address space of the passes' constant buffers (gpu::constants).
    pub constants: ConstantSpace,
    /// Errors wgpu reported outside an error scope, drained by `check_errors`.
    uncaptured: Arc<Mutex<Vec<String>>>,
}

fn backend_choice() -> Result<Vec<wgpu::Backends>, Error> {
    match std::env::var("SHADEMATRIX_BACKEND").ok().as_deref() {
        None | Some("") => Ok(vec![wgpu::Backends::VULKAN, wgpu::Backends::GL]),
        Some("vulkan") => Ok(vec![wgpu::Backends::VULKAN]),
        Some("gl") => Ok(vec![wgpu::Backends::GL]),
        Some(other) => Err(Error::Input(crate::input::names::unknown_name(
            "environment",
            "SHADEMATRIX_BACKEND",
            "backend",
            other,
            &["vulkan", "gl"],
        ))),
    }
}

fn type_rank(t: wgpu::DeviceType) -> u8 {
    match t {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Cpu => 3,
        wgpu::DeviceType::Other => 4,
    }
}

impl GpuContext {
    /// Vulkan first (timestamp queries, f64 shaders on lavapipe), GL only when Vulkan has no
    /// adapter; a real GPU before a CPU rasteriser. SHADEMATRIX_ADAPTER narrows by name.
    pub fn new() -> Result<GpuContext, Error> {
        let wanted_name = std::env::var("SHADEMATRIX_ADAPTER").ok().filter(|s| !s.is_empty());
        let mut seen = Vec::new();
        for backends in backend_choice()? {
            let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
            desc.backends = backends;
            let instance = wgpu::Instance::new(desc);
            let mut adapters = pollster::block_on(instance.enumerate_adapters(backends));
            for a in &adapters {
                let i = a.get_info();
                seen.push(format!("{} ({:?}, {:?})", i.name, i.backend, i.device_type));
            }
            if let Some(want) = &wanted_name {
                let want = want.to_lowercase();
                adapters.retain(|a| a.get_info().name.to_lowercase().contains(&want));
            }
            adapters.sort_by_key(|a| type_rank(a.get_info().device_type));
            if let Some(adapter) = adapters.into_iter().next() {
                return Self::open(adapter);
            }
        }
        let found = if seen.is_empty() { "none found".to_string() } else { format!("found {}", seen.join(", ")) };
        let filter = wanted_name.map(|n| format!(" matching SHADEMATRIX_ADAPTER=`{n}`")).unwrap_or_default();
        Err(Error::NoAdapter(format!("no adapter{filter} ({found}); {ADAPTER_HELP}")))
    }

    fn open(adapter: wgpu::Adapter) -> Result<GpuContext, Error> {
        let info = adapter.get_info();
        let constants = constant_space(&info)?;
        let timestamp = adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let mut required_features = wgpu::Features::empty();
        if timestamp {
            required_features |= wgpu::Features::TIMESTAMP_QUERY;
        }
        // Core WebGPU multisamples 4× and not 32-bit float targets; the adapter's own format
        // features allow the HDR target's MSAA and 2×/8× where the hardware has them.
        let adapter_formats = wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES;
        if adapter.features().contains(adapter_formats) {
            required_features |= adapter_formats;
        }
        // Built-in's ForwardAdd passes blend One One onto the 32-bit float HDR target.
        if !adapter.features().contains(wgpu::Features::FLOAT32_BLENDABLE) {
            return Err(Error::Device(format!(
                "{} cannot blend 32-bit float targets (FLOAT32_BLENDABLE), which built-in's additive \
                 ForwardAdd passes draw into",
                info.name
            )));
        }
        required_features |= wgpu::Features::FLOAT32_BLENDABLE;
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("shadematrix"),
            required_features,
            required_limits: adapter.limits(),
            ..Default::default()
        }))
        .map_err(|e| Error::Device(format!("cannot open device on {}: {e}", info.name)))?;
        let uncaptured = Arc::new(Mutex::new(Vec::new()));
        let sink = uncaptured.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            if let Ok(mut v) = sink.lock() {
                v.push(e.to_string());
            }
        }));
        let record = AdapterRecord {
            name: info.name.clone(),
            backend: format!("{:?}", info.backend).to_lowercase(),
            device_type: format!("{:?}", info.device_type),
            driver: info.driver.clone(),
            driver_info: info.driver_info.clone(),
            vendor: info.vendor,
            device: info.device,
            timestamp_queries: timestamp,
            constants,
        };
        Ok(GpuContext { adapter, device, queue, record, constants, uncaptured })
    }

    /// The MSAA sample counts (> 1) that every one of `formats` can render with and resolve.
    pub fn multisample_counts(&self, formats: &[wgpu::TextureFormat]) -> Vec<u32> {
        use wgpu::TextureFormatFeatureFlags as F;
        let adapter_formats = self.device.features().contains(wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES);
        [2, 4, 8, 16]
            .into_iter()
            .filter(|&n| {
                formats.iter().all(|&f| {
                    let flags = if adapter_formats {
                        self.adapter.get_texture_format_features(f).flags
                    } else {
                        f.guaranteed_format_features(self.device.features()).flags
                    };
                    let resolves = f.is_depth_stencil_format() || flags.contains(F::MULTISAMPLE_RESOLVE);
                    flags.sample_count_supported(n) && resolves
                })
            })
            .collect()
    }

    /// Turn errors wgpu reported asynchronously into a device error.
    pub fn check_errors(&self, during: &str) -> Result<(), Error> {
        let mut v = self.uncaptured.lock().map_err(|_| Error::Device("error sink poisoned".into()))?;
        if v.is_empty() {
            Ok(())
        } else {
            let all = v.drain(..).collect::<Vec<_>>().join("; ");
            Err(Error::Device(format!("{during}: {all}")))
        }
    }

    pub fn wait_idle(&self) -> Result<(), Error> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| Error::Device(format!("waiting for the GPU: {e}")))
    }

    /// Compile WGSL, reporting validation errors as a device error naming `label`.
    pub fn shader_module(&self, label: &str, source: &str) -> Result<wgpu::ShaderModule, Error> {
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = self.device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(label),
            source: wgpu::ShaderSource::Wgsl(self.constants.wgsl(source)),
        });
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(Error::Device(format!("shader `{label}` failed to compile: {e}")));
        }
        Ok(module)
    }
}
