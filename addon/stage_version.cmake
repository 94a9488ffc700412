# Writes the project's version (native/include/moldtex.h, read by the top CMakeLists.txt)
# into the staged add-on: bl_info's "version" in __init__.py and blender_manifest.toml's
# version, so neither can drift from the core's.
#   cmake -DSTAGE=<staged moldtex folder> -DVERSION=<major.minor.patch> -P stage_version.cmake
string(REPLACE "." ", " tuple "${VERSION}")
set(init "${STAGE}/__init__.py")
file(READ "${init}" text)
string(REGEX REPLACE "\"version\": \\([0-9]+, [0-9]+, [0-9]+\\)" "\"version\": (${tuple})" staged "${text}")
if(NOT staged MATCHES "\"version\": \\(${tuple}\\)")
  message(FATAL_ERROR "${init} has no bl_info \"version\": (a, b, c) entry to set")
endif()
file(WRITE "${init}" "${staged}")
set(manifest "${STAGE}/blender_manifest.toml")
file(READ "${manifest}" text)
string(REGEX REPLACE "\nversion = \"[0-9.]+\"" "\nversion = \"${VERSION}\"" staged "${text}")
if(NOT staged MATCHES "\nversion = \"${VERSION}\"")
  message(FATAL_ERROR "${manifest} has no version = \"...\" line to set")
endif()
file(WRITE "${manifest}" "${staged}")
