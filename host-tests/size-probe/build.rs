fn main() {
    // memory.x: the firmware's, from the one flash layout (the probe stands for the firmware).
    bridge_update::layout::build_script(bridge_update::layout::Image::Firmware);
    println!("cargo:rustc-link-arg-bins=-Tlink.x");
}
