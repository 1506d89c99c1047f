#!/usr/bin/env bash
# Re-creates bridge-fw/vendor/embassy-stm32 from the crates.io package embassy-stm32 0.6.0 plus
# patches/embassy-stm32-0.6.0-qemu.patch, or checks that it matches them.
#
#   ./vendor.sh           re-create vendor/embassy-stm32
#   ./vendor.sh --check   exit 1 if vendor/embassy-stm32 differs from release + patch
#   ./vendor.sh --diff    print the patch from the current vendor/ (after editing it)
#
# The package is taken from cargo's registry cache (it is there once any project has used
# embassy-stm32 0.6.0; this project's [patch] hides it from its own `cargo fetch`).
set -euo pipefail
cd "$(dirname "$0")"
version=0.6.0
patch=patches/embassy-stm32-$version-qemu.patch
dest=vendor/embassy-stm32

src=$(ls -d "${CARGO_HOME:-$HOME/.cargo}"/registry/src/*/embassy-stm32-$version 2>/dev/null | head -n1 || true)
if [[ -z "$src" ]]; then
    # Fetch the release with cargo through a throw-away project.
    tmp=$(mktemp -d)
    trap 'rm -rf "$tmp"' EXIT
    mkdir -p "$tmp/src" && touch "$tmp/src/lib.rs"
    printf '[package]\nname = "fetch"\nversion = "0.0.0"\nedition = "2021"\n[dependencies]\nembassy-stm32 = { version = "=%s", default-features = false, features = ["stm32l475vg"] }\n' \
        "$version" >"$tmp/Cargo.toml"
    cargo fetch --manifest-path "$tmp/Cargo.toml" >/dev/null
    src=$(ls -d "${CARGO_HOME:-$HOME/.cargo}"/registry/src/*/embassy-stm32-$version | head -n1)
fi

fresh=$(mktemp -d)
trap 'rm -rf "$fresh" ${tmp:+"$tmp"}' EXIT
cp -r "$src" "$fresh/embassy-stm32"
rm -f "$fresh/embassy-stm32/.cargo-ok"

case "${1:-}" in
--diff)
    (cd "$fresh/embassy-stm32" && for f in $(cd "$OLDPWD/$dest" && find . -type f ! -name .cargo-ok | sort); do
        diff -u --label "a/${f#./}" --label "b/${f#./}" "$f" "$OLDPWD/$dest/$f" || true
    done)
    exit 0
    ;;
esac

patch -s -d "$fresh/embassy-stm32" -p1 <"$patch"
if [[ "${1:-}" == --check ]]; then
    diff -r -x .cargo-ok "$fresh/embassy-stm32" "$dest" >/dev/null &&
        echo "vendor/embassy-stm32 = embassy-stm32 $version + $patch" ||
        { echo "vendor/embassy-stm32 differs from embassy-stm32 $version + $patch" >&2; exit 1; }
else
    rm -rf "$dest" && mkdir -p vendor && cp -r "$fresh/embassy-stm32" "$dest"
    echo "re-created $dest from embassy-stm32 $version + $patch"
fi
