# Shared set-up for scripts/play and scripts/test: installs what the build and the tests need on a fresh
# Debian or Ubuntu machine (apt, with sudo when not root), and checks for a Rust toolchain.
# Sourced, not run.

# ensure_packages PKG...: installs the Debian packages that are missing.
ensure_packages() {
    local missing=()
    local p
    for p in "$@"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
    done
    [ ${#missing[@]} -eq 0 ] && return 0
    if ! command -v apt-get >/dev/null 2>&1; then
        echo "scanline-racer: please install these packages (no apt-get here): ${missing[*]}" >&2
        return 1
    fi
    local sudo=()
    if [ "$(id -u)" -ne 0 ]; then
        if command -v sudo >/dev/null 2>&1; then
            sudo=(sudo)
        else
            echo "scanline-racer: not root and no sudo: run 'apt-get install -y ${missing[*]}' as root" >&2
            return 1
        fi
    fi
    echo "scanline-racer: installing ${missing[*]} ..." >&2
    DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get update -qq >&2 || true
    DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
}

# ensure_rust: cargo must be on PATH (rustup installs it); rust-version in Cargo.toml says which.
ensure_rust() {
    if ! command -v cargo >/dev/null 2>&1; then
        [ -x "$HOME/.cargo/bin/cargo" ] && export PATH="$HOME/.cargo/bin:$PATH"
    fi
    if ! command -v cargo >/dev/null 2>&1; then
        echo "scanline-racer: cargo not found: install Rust 1.95 or newer with rustup (https://rustup.rs)" >&2
        return 1
    fi
}

# Packages the build needs: pkg-config and libudev for gamepad support through gilrs; ALSA's headers for
# sound through cpal; a C compiler and libc headers for linking (and for the portable-maths test, which
# builds a stand-in maths library).
BUILD_PACKAGES=(pkg-config libudev-dev libasound2-dev gcc libc6-dev)
