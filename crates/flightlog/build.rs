//! Compiles proto/flapwing.proto (with protox, a pure-Rust protobuf compiler: no system
//! protoc) into the FileDescriptorSet that every log embeds as its flapwing schemas.

fn main() {
    println!("cargo:rerun-if-changed=proto/flapwing.proto");
    let fds = protox::Compiler::new(["proto"])
        .and_then(|mut c| {
            c.include_imports(true);
            c.open_file("flapwing.proto")?;
            Ok(c.encode_file_descriptor_set())
        })
        .unwrap_or_else(|e| panic!("proto/flapwing.proto: {e}"));
    let out = std::path::PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    std::fs::write(out.join("flapwing.fds"), fds).expect("cannot write the descriptor set");
}
