# Shared by the measurement scripts that stage public scenes (public-scenes.sh, era-scenes.sh):
# source it with `. "$(dirname "$0")/lib.sh"`. Reads only what its arguments name.

# gitdir MIRRORS OWNER+NAME: the git dir of a mirror (MIRRORS/OWNER+NAME/repo, bare or not, the
# layout the session's `fetch` tool writes).
gitdir() {
    local d="$1/$2/repo"
    [ -d "$d/.git" ] && d="$d/.git"
    [ -d "$d" ] || { echo "missing mirror $2 (fetch github:${2/+//})" >&2; return 1; }
    echo "$d"
}

# stage_one MIRRORS DEST NAME MIRROR LICENSE SCENE PATH...: copy SCENE and the PATHs (files or
# folders) of MIRROR's HEAD into DEST/NAME at their paths in the repository, and write
# DEST/NAME/SOURCE.txt (scene, repository, commit, paths, license, files the mirror lacks).
# Results already beside the scene's tree (ref.exr, ...) are kept.
stage_one() {
    local mirrors=$1 dest=$2 name=$3 mirror=$4 license=$5 scene=$6
    shift 6
    local paths=("$@") g out commit missing=0 mode type hash path
    g=$(gitdir "$mirrors" "$mirror") || return 1
    out="$dest/$name"
    mkdir -p "$out"
    commit=$(git -C "$g" rev-parse HEAD)
    for p in "$scene" "${paths[@]}"; do
        while IFS=$' \t' read -r mode type hash path; do
            [ "$type" = blob ] || continue
            mkdir -p "$out/$(dirname "$path")"
            if git -C "$g" cat-file -e "$hash" 2>/dev/null; then
                git -C "$g" cat-file blob "$hash" > "$out/$path"
            else
                echo "  $name: $path is not in the mirror (large file left out)" >&2
                missing=$((missing + 1))
            fi
        done < <(git -C "$g" ls-tree -r HEAD -- "$p")
    done
    {
        echo "scene:   $scene"
        echo "repo:    https://github.com/${mirror/+//}"
        echo "commit:  $commit"
        echo "paths:   $scene ${paths[*]}"
        echo "license: $license"
        echo "missing: $missing file(s)"
    } > "$out/SOURCE.txt"
    echo "$name: $out/$scene ($missing missing)"
}
