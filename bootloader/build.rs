//! The bootloader's `memory.x`, from the one flash layout (`bridge_update::layout`).

fn main() {
    bridge_update::layout::build_script(bridge_update::layout::Image::Bootloader);
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rustc-link-arg-bins=--nmagic");
    println!("cargo:rustc-link-arg-bins=-Tlink.x");
    println!("cargo:rustc-link-arg-bins=-Tdefmt.x");
}
