//! The `nimbus` binary: the command line of [`nimbus_cli`].

/// Generation allocates and frees many small values (IR nodes, names, printed text) and splits a
/// key's targets over every core: glibc's allocator took a fifth of a key's time, more when a
/// thread frees what another allocated. `nimbus bench` measured high's key, all six targets,
/// with mimalloc against glibc (see the README's generation costs).
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() -> std::process::ExitCode {
    nimbus_cli::main()
}
