//! GPU device setup and readback, written once for every GPU user: the
//! native headless renderer, the browser viewer and HairNet's WebGPU strand
//! decoder (natively and in the browser).
//!
//! - [`instance`]: a wgpu instance on the given backends (natively also the
//!   `WGPU_*` environment overrides).
//! - [`open_device`]: a device and queue under a limit set, clamped to
//!   what the adapter supports, with a lost-device report.
//! - [`map_read`]: a future that resolves when a buffer is mapped for
//!   reading (in the browser the event loop drives it; natively
//!   [`map_read_blocking`] polls the device).

use crate::error::{Error, Result};
use std::future::Future;
use std::pin::Pin;
use std::sync::{Arc, Mutex};
use std::task::{Context, Poll, Waker};

/// A wgpu instance restricted to `backends`. Natively the `WGPU_BACKEND`
/// and related environment variables can override the choice (as in
/// wgpu's examples); in the browser there is no environment.
pub fn instance(backends: wgpu::Backends) -> wgpu::Instance {
    #[cfg(not(target_arch = "wasm32"))]
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    #[cfg(target_arch = "wasm32")]
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
    desc.backends = backends;
    wgpu::Instance::new(desc)
}

/// A device and its queue on `adapter`, with `limits` raised to the
/// adapter's texture-size limits (`using_resolution`). `label` names the
/// user in errors and in the lost-device report, which goes to `on_lost`
/// (a message such as "deeprep viewer: GPU device lost (Destroyed): ...").
pub async fn open_device(
    adapter: &wgpu::Adapter,
    limits: wgpu::Limits,
    label: &'static str,
    on_lost: impl Fn(String) + Send + Sync + 'static,
) -> Result<(wgpu::Device, wgpu::Queue)> {
    let (device, queue) = adapter
        .request_device(&wgpu::DeviceDescriptor {
            label: Some(label),
            required_limits: limits.using_resolution(adapter.limits()),
            ..Default::default()
        })
        .await
        .map_err(|e| Error::Invalid(format!("{label}: GPU device: {e}")))?;
    device.set_device_lost_callback(move |reason, message| {
        on_lost(format!("{label}: GPU device lost ({reason:?}): {message}"))
    });
    Ok((device, queue))
}

#[derive(Default)]
struct MapState {
    done: Option<std::result::Result<(), wgpu::BufferAsyncError>>,
    waker: Option<Waker>,
}

/// The future of [`map_read`].
pub struct MapRead {
    state: Arc<Mutex<MapState>>,
}

/// Starts mapping `slice` for reading; the future resolves once it is
/// mapped (then read it with `slice.get_mapped_range()`), or with the
/// mapping's error.
pub fn map_read(slice: wgpu::BufferSlice<'_>) -> MapRead {
    let state = Arc::new(Mutex::new(MapState::default()));
    let s = state.clone();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let waker = match s.lock() {
            Ok(mut st) => {
                st.done = Some(r);
                st.waker.take()
            }
            Err(_) => None,
        };
        if let Some(w) = waker {
            w.wake();
        }
    });
    MapRead { state }
}

impl Future for MapRead {
    type Output = Result<()>;

    fn poll(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<Result<()>> {
        let mut st = match self.state.lock() {
            Ok(st) => st,
            Err(_) => return Poll::Ready(Err(Error::Invalid("GPU readback: poisoned".into()))),
        };
        match st.done.take() {
            Some(r) => Poll::Ready(r.map_err(|e| Error::Invalid(format!("GPU readback: {e}")))),
            None => {
                st.waker = Some(cx.waker().clone());
                Poll::Pending
            }
        }
    }
}

/// Native: maps `slice` for reading and waits for the GPU to finish.
#[cfg(not(target_arch = "wasm32"))]
pub fn map_read_blocking(device: &wgpu::Device, slice: wgpu::BufferSlice<'_>) -> Result<()> {
    let mapping = map_read(slice);
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| Error::Invalid(format!("GPU poll: {e}")))?;
    pollster::block_on(mapping)
}
