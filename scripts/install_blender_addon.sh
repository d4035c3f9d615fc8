#!/usr/bin/env bash
# Installs the FireLook add-on (samples/blender/firelook_addon) into Blender's user add-ons and
# enables it: Properties > Scene > FireLook. Copies the add-on (run it again after an update).
#   scripts/install_blender_addon.sh [BLENDER]        BLENDER: the program (default: blender)
# The add-on runs `firelook`: from its preferences, else $FIRELOOK_EXE, else the PATH.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
blender="${1:-blender}"
command -v "$blender" > /dev/null || { echo "install_blender_addon: $blender: not found (Debian: apt-get install blender)" >&2; exit 1; }
addons="$("$blender" -b --factory-startup --python-expr \
  "import bpy; print('ADDONS=' + bpy.utils.user_resource('SCRIPTS', path='addons', create=True))" 2>/dev/null |
  sed -n 's/^ADDONS=//p')"
[[ -n "$addons" ]] || { echo "install_blender_addon: $blender did not name its add-on folder" >&2; exit 1; }
rm -rf "$addons/firelook_addon"
cp -r "$root/samples/blender/firelook_addon" "$addons/firelook_addon"
"$blender" -b --python-exit-code 1 --python-expr \
  "import bpy; bpy.ops.preferences.addon_enable(module='firelook_addon'); bpy.ops.wm.save_userpref()" > /dev/null
echo "install_blender_addon: installed and enabled in $addons/firelook_addon"
