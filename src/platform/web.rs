//! The browser's side of the seam ([`crate::platform`]): a page writes no files (it offers
//! downloads), opens none by path (the bundled scenes, and what its file input picks), watches
//! none, and cannot block on the GPU (its answers arrive on the page's event loop). What goes
//! wrong is shown in the page (`#volley-error`); the run's facts are the canvas's `data-*`.
//!
//! The page's own start (its URL as the command line) is [`crate::app::web`].

use std::future::Future;
use std::path::{Path, PathBuf};

use wasm_bindgen::JsCast;
use winit::window::WindowAttributes;

use crate::SceneError;
use crate::scene::Scene;

/// The browser build.
pub const IN_BROWSER: bool = true;

/// A page writes no files: recordings, saved setups and screenshots are downloads.
pub const WRITES_FILES: bool = false;

/// A page cannot block: the GPU answers on the page's event loop, after the call returns.
pub const CAN_BLOCK: bool = false;

/// `None`: a page cannot wait for `future` here (it is dropped unpolled).
pub fn block_on<F: Future>(_future: F) -> Option<F::Output> {
    None
}

/// Spawns `future` on the page's event loop; `then` runs with its output once the browser has
/// answered, after this returns.
pub fn complete<F: Future + 'static>(future: F, then: impl FnOnce(F::Output) + 'static) {
    wasm_bindgen_futures::spawn_local(async move { then(future.await) });
}

/// An instance on the backends `?backend=` allows, without WebGPU where the browser has none.
pub async fn gpu_instance(mut descriptor: wgpu::InstanceDescriptor) -> wgpu::Instance {
    descriptor.backends = backends();
    wgpu::util::new_instance_with_webgpu_detection(descriptor).await
}

/// A GPU error the page did not expect is shown in it, not a silent stop.
pub fn report_gpu_errors(device: &wgpu::Device) {
    device.on_uncaptured_error(std::sync::Arc::new(|e: wgpu::Error| {
        show_error(&format!("GPU error: {e}"));
    }));
}

/// The window is a canvas, added to the page's body.
pub fn on_page(attributes: WindowAttributes) -> WindowAttributes {
    use winit::platform::web::WindowAttributesExtWebSys;
    attributes.with_append(true)
}

/// The picker's scene: a page has no files, so `assets/scenes/NAME.ron` is the bundled `NAME`.
pub fn load_scene(path: &Path) -> Result<Scene, SceneError> {
    let text = path.to_string_lossy();
    let name = text
        .strip_prefix("assets/scenes/")
        .and_then(|n| n.strip_suffix(".ron"))
        .unwrap_or(&text);
    crate::scene::bundled(name)
}

/// Offers `bytes` as a download named `name` (`folder` has no meaning in a page) and returns
/// `NAME (downloaded)` for the panel.
pub fn save_file(
    _folder: &Path,
    name: &str,
    bytes: &[u8],
    mime: &str,
) -> Result<PathBuf, (PathBuf, std::io::Error)> {
    download(name, bytes, mime);
    Ok(PathBuf::from(format!("{name} (downloaded)")))
}

/// Offers `bytes` as a download named `name` (a page's way of writing a file).
pub fn offer_download(name: &str, bytes: &[u8], mime: &str) {
    download(name, bytes, mime);
}

/// Offers the canvas's image as a PNG download named as the desktop's file. It is the canvas's
/// own image, taken in the task that drew the frame (a browser keeps a WebGPU canvas's image
/// only until then). Reading the frame back through a mapped buffer, as the desktop does
/// (`_write_png`), was refused by Chromium on SwiftShader here (the map's promise rejected,
/// with no GPU error).
pub fn save_screenshot(
    path: &Path,
    _write_png: impl FnOnce(&Path) -> Result<(), String>,
) -> Result<(), String> {
    let name = path
        .file_name()
        .map_or("volley.png".into(), |n| n.to_string_lossy().into_owned());
    download_canvas(&name);
    Ok(())
}

/// Puts `message` in the page's error element (made if missing) and the console.
pub fn show_error(message: &str) {
    web_sys::console::error_1(&message.into());
    let Some(document) = web_sys::window().and_then(|w| w.document()) else {
        return;
    };
    let element = document.get_element_by_id(ERROR_ID).or_else(|| {
        let e = document.create_element("pre").ok()?;
        e.set_id(ERROR_ID);
        document.body()?.append_child(&e).ok()?;
        Some(e)
    });
    if let Some(e) = element {
        e.set_text_content(Some(message));
    }
}

/// Sets each of `facts`, `(KEY, value)`, as the canvas's `data-KEY`.
pub fn show_on_page(facts: impl FnOnce() -> Vec<(&'static str, String)>) {
    if let Some(c) = canvas() {
        for (key, value) in facts() {
            let _ = c.set_attribute(&format!("data-{key}"), &value);
        }
    }
}

/// `false`: the browser build's plotters measures text with the page's fonts and has no font
/// rasteriser for PNG plots.
pub fn register_plot_font() -> bool {
    false
}

/// Nothing: a page's allocator has nothing to tune.
pub fn keep_freed_heap() {}

/// No watch: a page cannot watch files ([`FolderWatch::new`] refuses, and the panel says so).
pub struct FolderWatch {
    never: std::convert::Infallible,
}

impl FolderWatch {
    /// Refused: a page cannot watch files.
    pub fn new(_path: &Path) -> Result<FolderWatch, String> {
        Err("a browser page cannot watch files; load the scene again to see a change".into())
    }

    /// The watched file (there is none).
    pub fn path(&self) -> &Path {
        match self.never {}
    }

    /// Whether the file changed (there is none).
    pub fn touched(&mut self) -> bool {
        match self.never {}
    }
}

/// The id of the page element that shows an error.
pub const ERROR_ID: &str = "volley-error";

/// The URL's query parameter `key`, if given.
pub fn param(key: &str) -> Option<String> {
    let search = web_sys::window()?.location().search().ok()?;
    web_sys::UrlSearchParams::new_with_str(&search)
        .ok()?
        .get(key)
}

/// The backends `?backend=` allows: `webgl`, `webgpu`, or both (WebGPU where the browser has
/// it) when absent or anything else.
fn backends() -> wgpu::Backends {
    match param("backend").as_deref() {
        Some("webgl") => wgpu::Backends::GL,
        Some("webgpu") => wgpu::Backends::BROWSER_WEBGPU,
        _ => wgpu::Backends::GL | wgpu::Backends::BROWSER_WEBGPU,
    }
}

/// The canvas, once winit has added it.
fn canvas() -> Option<web_sys::HtmlCanvasElement> {
    let document = web_sys::window()?.document()?;
    document
        .query_selector("canvas")
        .ok()??
        .dyn_into::<web_sys::HtmlCanvasElement>()
        .ok()
}

/// Offers the canvas's current image as a PNG download named `name`; called in the task that
/// drew the frame, while the canvas still holds it.
fn download_canvas(name: &str) {
    let url = canvas().and_then(|c| c.to_data_url_with_type("image/png").ok());
    let Some(url) = url else {
        show_error(&format!("{name}: the canvas gave no image"));
        return;
    };
    click_download(name, &url);
}

/// Offers `bytes` as a download named `name`.
fn download(name: &str, bytes: &[u8], mime: &str) {
    let url = (|| {
        let parts = js_sys::Array::of1(&js_sys::Uint8Array::from(bytes));
        let options = web_sys::BlobPropertyBag::new();
        options.set_type(mime);
        let blob = web_sys::Blob::new_with_u8_array_sequence_and_options(&parts, &options).ok()?;
        web_sys::Url::create_object_url_with_blob(&blob).ok()
    })();
    match url {
        Some(url) => {
            click_download(name, &url);
            let _ = web_sys::Url::revoke_object_url(&url);
        }
        None => show_error(&format!("{name}: the browser refused the download")),
    }
}

/// Clicks a link to `url` that downloads it as `name`.
fn click_download(name: &str, url: &str) {
    let clicked = (|| {
        let document = web_sys::window()?.document()?;
        let a = document
            .create_element("a")
            .ok()?
            .dyn_into::<web_sys::HtmlAnchorElement>()
            .ok()?;
        a.set_href(url);
        a.set_download(name);
        a.click();
        Some(())
    })();
    if clicked.is_none() {
        show_error(&format!("{name}: the browser refused the download"));
    }
}

thread_local! {
    /// Files picked in the page's file input, (name, bytes), until the window takes them.
    static PICKED: std::cell::RefCell<Vec<(String, Vec<u8>)>> = const {
        std::cell::RefCell::new(Vec::new())
    };
}

/// The files picked in the page's file input since the last call, oldest first.
pub fn take_picked() -> Vec<(String, Vec<u8>)> {
    PICKED.with(|p| std::mem::take(&mut *p.borrow_mut()))
}

/// Reads every file picked in the page's `#volley-open` input (if the page has one) into
/// [`take_picked`]'s list.
pub fn listen_to_file_input() {
    use wasm_bindgen::closure::Closure;
    let Some(input) = web_sys::window()
        .and_then(|w| w.document())
        .and_then(|d| d.get_element_by_id("volley-open"))
        .and_then(|e| e.dyn_into::<web_sys::HtmlInputElement>().ok())
    else {
        return;
    };
    let target = input.clone();
    let on_change = Closure::<dyn FnMut(web_sys::Event)>::new(move |_: web_sys::Event| {
        let Some(files) = target.files() else {
            return;
        };
        for i in 0..files.length() {
            let Some(file) = files.get(i) else {
                continue;
            };
            wasm_bindgen_futures::spawn_local(async move {
                let name = file.name();
                match wasm_bindgen_futures::JsFuture::from(file.array_buffer()).await {
                    Ok(buffer) => {
                        let bytes = js_sys::Uint8Array::new(&buffer).to_vec();
                        PICKED.with(|p| p.borrow_mut().push((name, bytes)));
                    }
                    Err(_) => show_error(&format!("{name}: the browser could not read it")),
                }
            });
        }
        // The same file picked again is a change too.
        target.set_value("");
    });
    let _ = input.add_event_listener_with_callback("change", on_change.as_ref().unchecked_ref());
    // The page lives as long as the listener: nothing to drop it for.
    on_change.forget();
}
