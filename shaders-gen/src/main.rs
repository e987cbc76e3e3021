//! The `nimbus` binary: the command line of [`nimbus_cli`].

fn main() -> std::process::ExitCode {
    nimbus_cli::main()
}
