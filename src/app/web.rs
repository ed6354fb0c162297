//! The browser build's side of the window: the same [`App`](super) on winit's web backend,
//! started from the page (crates/volley-web), with the page's URL as its command line.
//!
//! - `?scene=NAME` opens a bundled scene (`seed` without one), `?scene=URL.ron` a scene or
//!   saved setup fetched from that URL; `?integrator=NAME` picks the
//!   integrator as `--integrator` does; `?backend=webgl` keeps to WebGL2 even where the
//!   browser has WebGPU (`webgpu` the other way; both, WebGPU first, without it). A name that is not one shows the CLI's one-line error in
//!   the page (`#volley-error`) instead of the window.
//! - `?replay=URL` fetches a recording (one `volley record` wrote, served beside the page or
//!   from any URL the page may fetch) and replays it, verifying every stored hash and keyframe.
//! - The canvas carries what a test or a curious user can read without a debugger:
//!   `data-frames` (frames drawn), `data-tick` (the first lane's tick), `data-scene`,
//!   `data-adapter`, `data-lanes` (the lanes' integrators, comma-separated), `data-aims` (how
//!   many lanes fired their last aim) and, while replaying, `data-replay` (the verdict line).
//!
//! What a page cannot do is said in the panel where it matters: there is no file to watch for
//! hot reload, and recordings, screenshots and PNG plots are not written (no file system).
//! The simulation runs on the page's one thread: rayon, finding no threads, runs every chunk
//! on it, which gives the same bits as any other thread count (docs/physics.md, "Determinism").

use std::path::PathBuf;

use wasm_bindgen::JsCast;
use winit::event_loop::EventLoop;
use winit::platform::web::EventLoopExtWebSys;

use super::session::replaying::ReplaySource;
use super::{App, Session, WindowOptions};

/// The id of the page element that shows an error.
pub const ERROR_ID: &str = "volley-error";

/// Opens the window in the page on the scene the URL names, or shows why not.
pub fn start() {
    std::panic::set_hook(Box::new(|info| {
        show_error(&format!("the page's Volley stopped: {info}"));
    }));
    listen_to_file_input();
    if let Err(message) = open() {
        show_error(&message);
    }
}

/// The URL's query parameter `key`, if given.
fn param(key: &str) -> Option<String> {
    let search = web_sys::window()?.location().search().ok()?;
    web_sys::UrlSearchParams::new_with_str(&search)
        .ok()?
        .get(key)
}

fn open() -> Result<(), String> {
    if let Some(url) = param("replay") {
        wasm_bindgen_futures::spawn_local(async move {
            if let Err(message) = open_replay(&url).await {
                show_error(&message);
            }
        });
        return Ok(());
    }
    let name = param("scene").unwrap_or_else(|| "seed".into());
    let bundled = crate::scene::BUNDLED.iter().any(|(n, _)| *n == name);
    if !bundled && name.ends_with(".ron") {
        wasm_bindgen_futures::spawn_local(async move {
            if let Err(message) = open_scene_url(&name).await {
                show_error(&message);
            }
        });
        return Ok(());
    }
    // A page has no files: a name that is not bundled gets the CLI's line for it.
    if !bundled {
        return Err(format!("error: {}", crate::no_such_scene(&name)));
    }
    let mut scene = crate::scene::bundled(&name).map_err(|e| format!("error: {e}"))?;
    if let Some(integrator) = param("integrator") {
        // The CLI's words for `--integrator` (src/cli/args.rs, parse_integrator).
        let parsed = crate::Integrator::parse(&integrator).ok_or_else(|| {
            let names: Vec<_> = crate::Integrator::ALL.iter().map(|i| i.name()).collect();
            format!(
                "error: ?integrator: unknown `{integrator}`, expected one of {}",
                names.join(", ")
            )
        })?;
        scene
            .set_integrator(parsed)
            .map_err(|e| format!("error: ?integrator={integrator}: {e}"))?;
    }
    let path = PathBuf::from(format!("assets/scenes/{name}.ron"));
    let compare = scene.compare.clone();
    let session = Session::with_lanes(scene, &path, compare.clone(), false);
    run(session, compare)
}

/// `?scene=URL.ron`: fetches a scene or saved setup and opens it, checked as `volley window
/// FILE` checks it (errors name the URL, line and column).
async fn open_scene_url(url: &str) -> Result<(), String> {
    let bytes = fetch(url).await.map_err(|e| format!("error: {url}: {e}"))?;
    let text = String::from_utf8(bytes).map_err(|_| format!("error: {url}: not UTF-8 text"))?;
    let stem = url
        .rsplit('/')
        .next()
        .unwrap_or(url)
        .trim_end_matches(".ron")
        .to_string();
    let scene = crate::scene::parse(&text, url, &stem).map_err(|e| format!("error: {e}"))?;
    let compare = scene.compare.clone();
    let session = Session::with_lanes(scene, &PathBuf::from(url), compare.clone(), false);
    run(session, compare)
}

/// `?replay=URL`: fetches the recording and replays it, verifying every stored hash and
/// keyframe as it goes; the verdict is the panel's and the canvas's `data-replay`.
async fn open_replay(url: &str) -> Result<(), String> {
    let bytes = fetch(url).await.map_err(|e| format!("error: {url}: {e}"))?;
    let source = ReplaySource::Bytes {
        name: PathBuf::from(url),
        bytes: bytes.into(),
    };
    let session = Session::for_replay_from(source, None).map_err(|e| format!("error: {e}"))?;
    run(session, Vec::new())
}

/// The bytes at `url`, or why not (the HTTP status, or the browser's reason).
async fn fetch(url: &str) -> Result<Vec<u8>, String> {
    use wasm_bindgen_futures::JsFuture;
    let reason = |e: wasm_bindgen::JsValue| {
        e.as_string()
            .or_else(|| js_sys::Error::from(e).message().as_string())
            .unwrap_or_else(|| "the request failed".into())
    };
    let window = web_sys::window().ok_or("no window")?;
    let response: web_sys::Response = JsFuture::from(window.fetch_with_str(url))
        .await
        .map_err(reason)?
        .dyn_into()
        .map_err(|_| "not an HTTP response".to_string())?;
    if !response.ok() {
        return Err(format!(
            "HTTP {} {}",
            response.status(),
            response.status_text()
        ));
    }
    let buffer = JsFuture::from(response.array_buffer().map_err(reason)?)
        .await
        .map_err(reason)?;
    Ok(js_sys::Uint8Array::new(&buffer).to_vec())
}

/// Opens the window on `session`.
fn run(session: Session, compare: Vec<crate::scene::CompareLane>) -> Result<(), String> {
    let options = WindowOptions {
        compare,
        equal_cost: false,
        exit_after_frames: None,
        screenshot: None,
        size: page_size(),
        frame_rate: None,
        paused: false,
        time_scale: 1.0,
        // Asked for so the panel says why a page has no hot reload.
        watch: true,
        scenes: crate::scene::BUNDLED
            .iter()
            .filter(|(n, _)| !n.starts_with("bench/"))
            .map(|(n, _)| {
                (
                    n.to_string(),
                    PathBuf::from(format!("assets/scenes/{n}.ron")),
                )
            })
            .collect(),
        record: None,
        surface_drill: false,
        script: Vec::new(),
        history_budget: crate::timeline::DEFAULT_BUDGET,
        warm_up_ticks: 0,
        display: None,
        policy: crate::pacing::DEFAULT_POLICY.with_refresh(super::display::DEFAULT_REFRESH),
        draw: crate::pacing::DEFAULT_DRAW,
    };
    let event_loop = EventLoop::new().map_err(|e| format!("error: no event loop: {e}"))?;
    event_loop.spawn_app(App::new(session, options));
    Ok(())
}

/// The page's inner size (CSS px), the window's first size.
fn page_size() -> (u32, u32) {
    let size = web_sys::window().and_then(|w| {
        let width = w.inner_width().ok()?.as_f64()?;
        let height = w.inner_height().ok()?.as_f64()?;
        Some((width as u32, height as u32))
    });
    size.filter(|&(w, h)| w >= 320 && h >= 240)
        .unwrap_or((1280, 800))
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

/// The canvas, once winit has added it.
fn canvas() -> Option<web_sys::HtmlCanvasElement> {
    let document = web_sys::window()?.document()?;
    document
        .query_selector("canvas")
        .ok()??
        .dyn_into::<web_sys::HtmlCanvasElement>()
        .ok()
}

/// Sets `data-KEY` on the canvas.
fn set_data(key: &str, value: &str) {
    if let Some(c) = canvas() {
        let _ = c.set_attribute(&format!("data-{key}"), value);
    }
}

/// After a frame: the frame count, the first lane's tick, the scene's name, the lanes'
/// integrators and how many of them fired their last aim, and while replaying, the replay's
/// verdict line (the one `volley replay --verify` prints) on the canvas.
pub fn after_frame(session: &Session, frames: u64) {
    set_data("frames", &frames.to_string());
    set_data("tick", &session.world().tick().to_string());
    set_data("scene", &session.scene().name);
    let lanes: Vec<&str> = session
        .lanes()
        .iter()
        .map(|lane| lane.sim.world.integrator().name())
        .collect();
    set_data("lanes", &lanes.join(","));
    let fired = session
        .lanes()
        .iter()
        .filter(|lane| lane.aim.as_ref().is_some_and(|aim| aim.outcome.is_ok()))
        .count();
    set_data("aims", &fired.to_string());
    if let Some(verdict) = session.replay_verdict() {
        set_data("replay", &verdict.line());
    }
}

/// The adapter the browser gave, on the canvas.
pub fn show_adapter(adapter: &str) {
    set_data("adapter", adapter);
}

/// The picker's scene: a page has no files, so `assets/scenes/NAME.ron` is the bundled `NAME`.
pub fn load(path: &std::path::Path) -> Result<crate::Scene, crate::SceneError> {
    let text = path.to_string_lossy();
    let name = text
        .strip_prefix("assets/scenes/")
        .and_then(|n| n.strip_suffix(".ron"))
        .unwrap_or(&text);
    crate::scene::bundled(name)
}

/// The backends `?backend=` allows: `webgl`, `webgpu`, or both (WebGPU where the browser has
/// it) when absent or anything else.
pub fn backends() -> wgpu::Backends {
    match param("backend").as_deref() {
        Some("webgl") => wgpu::Backends::GL,
        Some("webgpu") => wgpu::Backends::BROWSER_WEBGPU,
        _ => wgpu::Backends::GL | wgpu::Backends::BROWSER_WEBGPU,
    }
}

/// Offers the canvas's current image as a PNG download named `name`; called in the task that
/// drew the frame, while the canvas still holds it.
pub fn download_canvas(name: &str) {
    let url = canvas().and_then(|c| c.to_data_url_with_type("image/png").ok());
    let Some(url) = url else {
        show_error(&format!("{name}: the canvas gave no image"));
        return;
    };
    click_download(name, &url);
}

/// Offers `bytes` as a download named `name` (a page's way of writing a file).
pub fn download(name: &str, bytes: &[u8], mime: &str) {
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

/// The files picked since the last call, oldest first.
pub fn take_picked() -> Vec<(String, Vec<u8>)> {
    PICKED.with(|p| std::mem::take(&mut *p.borrow_mut()))
}

/// Reads every file picked in the page's `#volley-open` input (if the page has one) into
/// [`take_picked`]'s list.
fn listen_to_file_input() {
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
