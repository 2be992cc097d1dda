# Sourced by the wasm scripts: selects Debian's rustc-web toolchain (1.96,
# with its std source for -Zbuild-std, since `rustup target add` cannot
# download here) for every tool that calls cargo or rustc (wasm-pack too).
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
SHIM="$ROOT/target/wasm-toolchain/bin"
mkdir -p "$SHIM"
for t in cargo rustc rustdoc; do ln -sf "/usr/bin/$t" "$SHIM/$t"; done
# Debian's clippy for the same toolchain (rust-web-clippy), when installed
for t in cargo-clippy clippy-driver; do [ -x "/usr/bin/$t" ] && ln -sf "/usr/bin/$t" "$SHIM/$t"; done
export PATH="$SHIM:$HOME/.cargo/bin:$PATH"
export RUSTC=/usr/bin/rustc RUSTDOC=/usr/bin/rustdoc RUSTC_BOOTSTRAP=1
# One flag set for every wasm build (library, tests, wasm-pack), so the
# dependency graph is compiled once per profile. `test` is in the build-std
# set for the library too: `cargo test` needs it, and a different set gives
# std a different hash, which would rebuild every dependency (tract) twice.
WASM_CARGO_FLAGS=(--target wasm32-unknown-unknown -Zbuild-std=std,panic_abort,test)
export CHROMEDRIVER=/usr/bin/chromedriver
