# Writes OUTPUT: a C++ file defining moldtex::cl::program_source(), the OpenCL program
# made of the INPUTS (a |-separated list of files) in order. Run with cmake -P.
string(REPLACE "|" ";" INPUTS "${INPUTS}")
set(text "")
foreach(file IN LISTS INPUTS)
  file(READ "${file}" content)
  get_filename_component(name "${file}" NAME)
  string(APPEND text "/* ---- ${name} ---- */\n${content}\n")
endforeach()
file(WRITE "${OUTPUT}.tmp"
  "// Generated from the shared sources and kernels.cl; do not edit.\n"
  "#include <string>\nnamespace moldtex::cl {\n"
  "const std::string& program_source() {\n"
  "  static const std::string source = R\"MTXCL(${text})MTXCL\";\n"
  "  return source;\n}\n}  // namespace moldtex::cl\n")
execute_process(COMMAND ${CMAKE_COMMAND} -E copy_if_different "${OUTPUT}.tmp" "${OUTPUT}")
