//! Device setup: one wgpu instance, adapter, device and queue, with or without a window.
//!
//! wgpu picks whatever adapter the machine has; on a machine without a GPU that is a software
//! rasteriser (Mesa's lavapipe through Vulkan, llvmpipe through GL), which is what CI runs on.
//! `WGPU_BACKEND=vulkan|gl` and `WGPU_ADAPTER_NAME=...` choose among several (wgpu's own
//! environment variables). Failing to find one is an ordinary error, never a panic, so the
//! command line can print one line that points at the headless mode instead.

/// An open device and what it was opened on.
#[derive(Debug)]
pub struct Gpu {
    /// The instance the adapter came from (surfaces are created from it).
    pub instance: wgpu::Instance,
    /// The adapter in use.
    pub adapter: wgpu::Adapter,
    /// The logical device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
}

/// Why no device could be opened.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum GpuError {
    /// No adapter at all (or none that can present to the window).
    NoAdapter(String),
    /// An adapter was found but refused to open a device.
    Device(String),
    /// The window's surface could not be created.
    Surface(String),
}

impl std::fmt::Display for GpuError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            GpuError::NoAdapter(why) => write!(f, "no GPU adapter found ({why})"),
            GpuError::Device(why) => write!(f, "the GPU adapter would not open a device ({why})"),
            GpuError::Surface(why) => write!(f, "cannot create a drawing surface ({why})"),
        }
    }
}

impl std::error::Error for GpuError {}

impl Gpu {
    /// A device with no window, for offscreen frames and tests (the desktop's: it blocks until
    /// the GPU has answered).
    pub fn headless() -> Result<Gpu, GpuError> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        Gpu::open(instance, None)
    }

    /// A device on `instance` that can present to `surface` (if given), blocking until the GPU
    /// has answered; a page, which cannot block ([`crate::platform::CAN_BLOCK`]), gets an error
    /// naming [`Gpu::open_async`].
    pub fn open(
        instance: wgpu::Instance,
        surface: Option<&wgpu::Surface<'_>>,
    ) -> Result<Gpu, GpuError> {
        crate::platform::block_on(Gpu::open_async(instance, surface)).unwrap_or_else(|| {
            Err(GpuError::NoAdapter(
                "a page cannot block on the GPU: open it with Gpu::open_async".into(),
            ))
        })
    }

    /// [`Gpu::open`] as a future: the browser build awaits it (a page cannot block on the GPU),
    /// the desktop one blocks on it.
    pub async fn open_async(
        instance: wgpu::Instance,
        surface: Option<&wgpu::Surface<'_>>,
    ) -> Result<Gpu, GpuError> {
        let options = wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::from_env().unwrap_or_default(),
            compatible_surface: surface,
            ..Default::default()
        };
        let adapter = instance
            .request_adapter(&options)
            .await
            .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        // WebGL2 (a GL adapter in a browser) has fewer of everything than the downlevel
        // defaults ask for.
        let webgl2 = adapter.get_info().backend == wgpu::Backend::Gl && crate::platform::IN_BROWSER;
        let base = if webgl2 {
            wgpu::Limits::downlevel_webgl2_defaults()
        } else {
            wgpu::Limits::downlevel_defaults()
        };
        let descriptor = wgpu::DeviceDescriptor {
            label: Some("volley"),
            required_limits: base.using_resolution(adapter.limits()),
            ..Default::default()
        };
        let (device, queue) = adapter
            .request_device(&descriptor)
            .await
            .map_err(|e| GpuError::Device(e.to_string()))?;
        Ok(Gpu {
            instance,
            adapter,
            device,
            queue,
        })
    }

    /// One line naming the adapter and backend, for the panel and for logs.
    pub fn describe(&self) -> String {
        let info = self.adapter.get_info();
        format!("{} ({:?}, {:?})", info.name, info.backend, info.device_type)
    }

    /// Whether a window's surface texture can be viewed in another format that differs only in
    /// sRGB encoding (wgpu's `SURFACE_VIEW_FORMATS`; Vulkan's mutable-format swapchains).
    pub fn surface_view_formats(&self) -> bool {
        self.adapter
            .get_downlevel_capabilities()
            .flags
            .contains(wgpu::DownlevelFlags::SURFACE_VIEW_FORMATS)
    }

    /// Blocks until every submitted command has finished.
    pub fn wait(&self) {
        // A poll error means the device is lost; the next submit reports it, so it is dropped.
        let _ = self.device.poll(wgpu::PollType::wait_indefinitely());
    }
}
