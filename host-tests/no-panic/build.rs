fn main() {
    // memory.x from the one flash layout: the whole flash (linked to prove, never flashed:
    // at opt-level 3 its code is larger than a slot).
    bridge_update::layout::build_script(bridge_update::layout::Image::LinkOnly);
    println!("cargo:rustc-link-arg-bins=-Tlink.x");
}
