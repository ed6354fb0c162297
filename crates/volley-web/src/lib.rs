//! Volley's window in a browser: the page (static/index.html) loads this module, whose start
//! function opens the same window the desktop build opens, on winit's web backend
//! (`volley::app::web`). Built by `scripts/web`; docs/window.md, "In a browser", says what
//! differs from the desktop.

#[cfg(target_arch = "wasm32")]
mod browser {
    use wasm_bindgen::prelude::wasm_bindgen;

    /// Runs when the page instantiates the module.
    #[wasm_bindgen(start)]
    pub fn start() {
        volley::app::web::start();
    }
}
