# Sourced by run.sh, run_live.sh and run_bake.sh: a script of tests/blender run in real headless
# Blender against the real tessera-server, the add-on as a user installs it.
# blender_run SOURCE_DIR WORK SCRIPT SERVER_BINARY: the Python client installed from its wheel into
# WORK/venv, the add-on enabled from a scratch scripts folder (WORK/scripts), then
# tests/blender/SCRIPT run in Blender with WORK/out and SERVER_BINARY after "--".
blender_run() {
  local source_dir="$1" work="$2" script="$3" server="$4" site
  if ! command -v blender > /dev/null; then
    echo "blender is not installed (tools/install-deps.sh installs Debian's)"
    exit 1
  fi
  "$source_dir/tests/python/install-client.sh" "$source_dir" "$work"
  mkdir -p "$work/scripts/addons" "$work/out"
  ln -sfn "$source_dir/client/blender/tessera_subdiv" "$work/scripts/addons/tessera_subdiv"
  site=$("$work/venv/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
  export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$work}"
  BLENDER_USER_SCRIPTS="$work/scripts" PYTHONPATH="$site" \
    blender -b --factory-startup --python-use-system-env --python-exit-code 1 \
      --python "$source_dir/tests/blender/$script" -- "$work/out" "$server"
}
