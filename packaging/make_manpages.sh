#!/bin/sh
# make_manpages.sh GLCAST OUTDIR VERSION: the manual pages glcast(1) and glcast-COMMAND(1), one
# per command that `glcast --help` lists, made by help2man from the same --help text the command
# prints (so they cannot drift from it), gzipped as Debian installs them.
set -eu
glcast=$1 out=$2 version=$3
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# What every page ends with: where the rest is written down.
cat > "$work/see-also.h2m" <<'EOF'
[SEE ALSO]
.BR glcast (1),
and the documents in
.IR /usr/share/doc/glcast/ :
architecture.md (how the parts fit), wall.md (running a wall), display-configs.md,
environment.md (the shim's GLCAST_* variables), security.md (keys), reliability.md.
EOF

help2man --no-info --version-string="$version" --include="$work/see-also.h2m" \
    --name="put unmodified OpenGL programs on display walls" --output="$work/glcast.1" "$glcast"

# The commands and their one-line descriptions, from the "Commands:" section of glcast --help.
"$glcast" --help | awk '/^Commands:/ {on = 1; next} on && /^  [a-z]/ {print}' |
while read -r command description; do
    [ "$command" = help ] && continue
    wrapper="$work/glcast-$command"
    printf '#!/bin/sh\nexec "%s" %s "$@"\n' "$glcast" "$command" > "$wrapper"
    chmod +x "$wrapper"
    help2man --no-info --version-string="$version" --include="$work/see-also.h2m" \
        --name="$description" --output="$work/glcast-$command.1" "$wrapper"
done

for page in "$work"/*.1; do
    gzip -9n < "$page" > "$out/$(basename "$page").gz"
done
