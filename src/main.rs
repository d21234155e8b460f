fn main() {
    eprintln!("omnicloud: the command line is being built");
}
