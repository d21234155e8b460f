//! Headless wgpu device creation and error capture.

use std::sync::{Arc, Mutex};

use super::error::RasterError;

/// A headless device and queue, with the adapter's name and the limits granted.
pub struct GpuContext {
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// Adapter name and backend, e.g. `llvmpipe (LLVM 15.0.6, 256 bits) (Vulkan)`.
    pub adapter_name: String,
    /// What the adapter says of itself (driver, vendor, device: the pipeline cache's key).
    pub adapter_info: wgpu::AdapterInfo,
    /// True when the device has `PIPELINE_CACHE`.
    pub pipeline_cache: bool,
    /// Limits granted to the device.
    pub limits: wgpu::Limits,
    /// True when the device has `TIMESTAMP_QUERY`.
    pub timestamps: bool,
    /// True when the device has 64-bit storage atomics (`atomicMax` on `atomic<u64>`), which
    /// the compute splat path needs.
    pub int64_atomics: bool,
    lost: Arc<Mutex<Option<String>>>,
    uncaptured: Arc<Mutex<Option<String>>>,
}

impl GpuContext {
    /// Creates a device on the best adapter: Vulkan first, then any backend.
    pub fn new() -> Result<Self, RasterError> {
        // Probe Vulkan alone first: the GL backend's EGL probing prints display-server
        // errors on headless machines, and Vulkan is what we want wherever it exists.
        // Only adapters that can render the distance channel count: OpenGL ES without
        // EXT_color_buffer_float (Mesa's GL fallback) cannot, and would fail at the pipelines.
        let enumerate = |backends: wgpu::Backends| {
            let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
            desc.backends = backends;
            let instance = wgpu::Instance::new(desc);
            let mut adapters = pollster::block_on(instance.enumerate_adapters(backends));
            adapters.retain(|a| {
                a.get_texture_format_features(super::formats::DISTANCE_FORMAT)
                    .allowed_usages
                    .contains(wgpu::TextureUsages::RENDER_ATTACHMENT)
            });
            adapters
        };
        let mut adapters = enumerate(wgpu::Backends::VULKAN);
        if adapters.is_empty() {
            adapters = enumerate(wgpu::Backends::all() - wgpu::Backends::VULKAN);
        }
        let rank = |a: &wgpu::Adapter| {
            let info = a.get_info();
            let backend = if info.backend == wgpu::Backend::Vulkan {
                0
            } else {
                1
            };
            let kind = match info.device_type {
                wgpu::DeviceType::DiscreteGpu => 0,
                wgpu::DeviceType::IntegratedGpu => 1,
                wgpu::DeviceType::VirtualGpu => 2,
                wgpu::DeviceType::Cpu => 3,
                wgpu::DeviceType::Other => 4,
            };
            (backend, kind)
        };
        let adapter = adapters
            .into_iter()
            .min_by_key(rank)
            .ok_or(RasterError::NoAdapter)?;
        let info = adapter.get_info();
        let adapter_name = format!("{} ({:?})", info.name, info.backend);
        // Ask for everything the adapter offers: the storage-binding and buffer sizes bound the
        // chunk sizes, and nothing else here depends on lower limits.
        let limits = adapter.limits();
        let timestamps = adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let int64 = wgpu::Features::SHADER_INT64 | wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX;
        let int64_atomics = adapter.features().contains(int64);
        let mut required_features = wgpu::Features::empty();
        if timestamps {
            required_features |= wgpu::Features::TIMESTAMP_QUERY;
        }
        if int64_atomics {
            required_features |= int64;
        }
        let pipeline_cache = adapter.features().contains(wgpu::Features::PIPELINE_CACHE);
        if pipeline_cache {
            required_features |= wgpu::Features::PIPELINE_CACHE;
        }
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("omnicloud raster"),
            required_features,
            required_limits: limits.clone(),
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        }))
        .map_err(|e| RasterError::DeviceRequest {
            adapter: adapter_name.clone(),
            reason: e.to_string(),
        })?;
        let lost = Arc::new(Mutex::new(None));
        let lost_cb = lost.clone();
        device.set_device_lost_callback(move |reason, message| {
            if let Ok(mut slot) = lost_cb.lock() {
                *slot = Some(format!("{reason:?}: {message}"));
            }
        });
        let uncaptured = Arc::new(Mutex::new(None));
        let uncaptured_cb = uncaptured.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            if let Ok(mut slot) = uncaptured_cb.lock() {
                slot.get_or_insert_with(|| e.to_string());
            }
        }));
        Ok(GpuContext {
            device,
            queue,
            adapter_name,
            adapter_info: info,
            pipeline_cache,
            limits,
            timestamps,
            int64_atomics,
            lost,
            uncaptured,
        })
    }

    /// Runs `f` inside out-of-memory and validation error scopes and reports what they caught
    /// (and any loss of the device) as a [`RasterError`] naming `what`.
    pub fn scoped<T>(&self, what: &str, f: impl FnOnce() -> T) -> Result<T, RasterError> {
        let oom = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let out = f();
        let v = pollster::block_on(validation.pop());
        let o = pollster::block_on(oom.pop());
        if let Some(e) = o {
            return Err(RasterError::OutOfMemory {
                while_doing: what.to_string(),
                message: e.to_string(),
            });
        }
        if let Some(e) = v {
            return Err(RasterError::Gpu {
                while_doing: what.to_string(),
                message: e.to_string(),
            });
        }
        self.check(what)?;
        Ok(out)
    }

    /// Waits for all submitted work; reports device loss or uncaptured errors.
    pub fn wait(&self, what: &str) -> Result<(), RasterError> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| RasterError::Gpu {
                while_doing: what.to_string(),
                message: e.to_string(),
            })?;
        self.check(what)
    }

    /// Device loss or an uncaptured error since the last check, as an error.
    pub fn check(&self, what: &str) -> Result<(), RasterError> {
        if let Some(m) = self.lost.lock().ok().and_then(|s| s.clone()) {
            return Err(RasterError::DeviceLost(m));
        }
        if let Some(m) = self.uncaptured.lock().ok().and_then(|mut s| s.take()) {
            return Err(RasterError::Gpu {
                while_doing: what.to_string(),
                message: m,
            });
        }
        Ok(())
    }
}
