#!/usr/bin/env bash
# Packs what tools/gpu_bench.sh needs on a machine without Rust or a Vulkan loader (the lent
# GPU machine): stripped release builds of omnicloud and gen_big_las, and the Vulkan loader
# package, in .gpu/ (git-ignored, about 17 MB). Run it here, then carry .gpu with the working
# tree and run tools/gpu_bench.sh there; it uses the bundle when it finds one.
#
#   tools/gpu_bundle.sh            (writes .gpu/bin and .gpu/debs)
set -euo pipefail
cd "$(dirname "$0")/.."

cargo build --release --quiet --bin omnicloud --example gen_big_las --example live_bench
rm -rf .gpu
mkdir -p .gpu/bin .gpu/debs
for b in target/release/omnicloud target/release/examples/gen_big_las \
  target/release/examples/live_bench; do
  strip -o ".gpu/bin/$(basename "$b")" "$b"
done

# The Vulkan loader (libvulkan.so.1) for x86-64, unpacked there only when it has none.
lists=$(mktemp -d)
mkdir -p "$lists/partial"
apt=(-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oAPT::Sandbox::User=root
  "-oDir::State::Lists=$lists")
apt-get "${apt[@]}" update -qq
(cd .gpu/debs && apt-get "${apt[@]}" download libvulkan1 2>/dev/null)
rm -rf "$lists"

# The binaries must start on an older C library than this machine's.
glibc=$(objdump -T .gpu/bin/omnicloud | grep -o 'GLIBC_[0-9.]*' | sort -V | tail -1)
echo "bundle: $(du -sh .gpu | cut -f1) in .gpu (omnicloud needs ${glibc:-no GLIBC symbols})" >&2
ls -l .gpu/bin .gpu/debs >&2
