#!/bin/sh
# tools/fetch_cgal_data.sh DIR -- puts CGAL's sample data used by the spline demos into DIR:
#   skull_2.9.inr (64^3 float), liver.inr.gz (438x353x165 uint8), armadillo.off, bunny00.off;
#   and for the SLIM builder: kitten.xyz, sphere_20k_normal.xyz (oriented points), fandisk.off,
#   ChineseDragon-10kv.off.
# They come from data.tar.gz in the Debian package libcgal-demo, fetched with `apt-get download`
# (no installation, no dependencies) and unpacked with `dpkg -x`. Does nothing when all the
# files are already there. Needs apt-get, dpkg-deb and tar (Debian/Ubuntu).
set -eu
dir=${1:?usage: fetch_cgal_data.sh DIR}
files="skull_2.9.inr liver.inr.gz armadillo.off bunny00.off kitten.xyz sphere_20k_normal.xyz fandisk.off ChineseDragon-10kv.off"

missing=""
for f in $files; do [ -s "$dir/$f" ] || missing="$missing $f"; done
if [ -z "$missing" ]; then
  echo "CGAL data present in $dir"
  exit 0
fi

mkdir -p "$dir"
dir=$(cd "$dir" && pwd)
tmp=$(mktemp -d "$dir/.fetch.XXXXXX")
trap 'rm -rf "$tmp"' EXIT INT TERM
echo "fetching libcgal-demo (CGAL sample data, about 25 MB) for:$missing"
# Without package lists (a machine where every other package was already installed and `apt-get
# update` never ran) the download fails: update them once (as root, or through sudo) and retry.
download() { (cd "$tmp" && apt-get download libcgal-demo >/dev/null 2>"$tmp/apt.log"); }
download || {
  sudo=""; [ "$(id -u)" = 0 ] || sudo="sudo -n"  # -n: never wait for a password
  echo "fetch_cgal_data.sh: 'apt-get download libcgal-demo' failed; running 'apt-get update' and retrying" >&2
  { $sudo apt-get update -qq >"$tmp/update.log" 2>&1 && download; } || {
    echo "fetch_cgal_data.sh: 'apt-get download libcgal-demo' failed:" >&2
    cat "$tmp/update.log" "$tmp/apt.log" >&2 2>/dev/null || true
    exit 1
  }
}
dpkg -x "$tmp"/libcgal-demo_*.deb "$tmp/pkg"
tarball=$(find "$tmp/pkg" -name data.tar.gz | head -n 1)
[ -n "$tarball" ] || { echo "fetch_cgal_data.sh: data.tar.gz not found in libcgal-demo" >&2; exit 1; }
listing="$tmp/list"
tar -tzf "$tarball" >"$listing"
for f in $missing; do
  path=$(grep -m 1 "/$f\$" "$listing" || true)
  [ -n "$path" ] || { echo "fetch_cgal_data.sh: $f not found in $tarball" >&2; exit 1; }
  tar -xzf "$tarball" -C "$tmp" "$path"
  mv "$tmp/$path" "$dir/$f.part" && mv "$dir/$f.part" "$dir/$f"
  echo "  $dir/$f  (data.tar.gz: $path)"
done
