//! Links the `luamotion` executable with its segments on 2 MiB boundaries (Linux), so that
//! the kernel loads its code at a 2 MiB-aligned address and nearly all of it can be backed
//! by huge pages before the RT thread's first cycle (`rt_core::huge_pages`).

fn main() {
    if std::env::var("CARGO_CFG_TARGET_OS").as_deref() == Ok("linux") {
        println!("cargo:rustc-link-arg-bins=-Wl,-z,max-page-size=0x200000,-z,separate-loadable-segments");
    }
}
