# Writes the project's version (native/include/moldtex.h, read by the top CMakeLists.txt)
# into the staged add-on: bl_info's "version" in __init__.py and blender_manifest.toml's
# version, so neither can drift from the core's.
#   cmake -DSTAGE=<staged moldtex folder> -DVERSION=<major.minor.patch> -P stage_version.cmake

# Replaces `pattern` in `file` by `replacement`, which must then be found there.
function(stage_version file pattern replacement what)
  file(READ "${file}" text)
  string(REGEX REPLACE "${pattern}" "${replacement}" staged "${text}")
  string(FIND "${staged}" "${replacement}" found)
  if(found EQUAL -1)
    message(FATAL_ERROR "${file} has no ${what} to set")
  endif()
  file(WRITE "${file}" "${staged}")
endfunction()

# No byte code from the source tree (a package run from addon/ leaves __pycache__ folders).
file(GLOB_RECURSE caches LIST_DIRECTORIES true "${STAGE}/*")
list(FILTER caches INCLUDE REGEX "/__pycache__$")
if(caches)
  file(REMOVE_RECURSE ${caches})
endif()

string(REPLACE "." ", " tuple "${VERSION}")
stage_version("${STAGE}/__init__.py" "\"version\": \\([0-9]+, [0-9]+, [0-9]+\\)" "\"version\": (${tuple})"
              "bl_info \"version\": (a, b, c) entry")
stage_version("${STAGE}/blender_manifest.toml" "\nversion = \"[0-9.]+\"" "\nversion = \"${VERSION}\""
              "version = \"...\" line")
