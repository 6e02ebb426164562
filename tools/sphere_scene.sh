#!/bin/sh
# tools/sphere_scene.sh N [SEED] > scene.json -- the scene of `quadcast bench spheres` as a JSON
# scene file, for timing `quadcast render` on large files: N random spheres in the unit cube of
# radius 0.3 N^(-1/3), a 30 degree perspective camera from (0.5, 0.5, 3) looking at
# (0.5, 0.5, 0.5). One sphere per line, numbers with 5 decimals (about 65 bytes a sphere), so
# 1M spheres fit the scene file size limit. Render at the benchmark's 1024x768 (the default):
#     tools/sphere_scene.sh 1000000 > big.json
#     /usr/bin/time -v quadcast render big.json -o big.png
set -eu
if [ $# -lt 1 ] || [ $# -gt 2 ]; then
    echo "usage: $0 N [SEED] > scene.json" >&2
    exit 2
fi
case $1 in
    ''|*[!0-9]*) echo "$0: N must be a positive integer, got '$1'" >&2; exit 2 ;;
esac
if [ "$1" -lt 1 ]; then
    echo "$0: N must be a positive integer, got '$1'" >&2
    exit 2
fi
exec awk -v n="$1" -v seed="${2:-1}" 'BEGIN {
    srand(seed)
    r = 0.3 * exp(-log(n) / 3)
    printf "{\"camera\": {\"eye\": [0.5, 0.5, 3], \"target\": [0.5, 0.5, 0.5], \"fov_y\": 30},\n"
    printf " \"objects\": [\n"
    for (i = 0; i < n; ++i)
        printf "{\"sphere\":{\"center\":[%.5f,%.5f,%.5f],\"radius\":%.6g}}%s\n", rand(), rand(), rand(), r, i + 1 < n ? "," : ""
    printf "]}\n"
}'
