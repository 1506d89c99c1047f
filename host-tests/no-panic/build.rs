fn main() {
    // memory.x (STM32L475VG) is found in the workspace root, where the linker runs.
    println!("cargo:rustc-link-arg-bins=-Tlink.x");
}
