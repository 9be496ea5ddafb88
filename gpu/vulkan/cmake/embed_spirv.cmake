# Turns one SPIR-V binary into a C++ source defining its words as a uint32_t array, so the
# library carries its shaders and needs no files at run time.
# Inputs: SPV (binary), OUT (generated .cpp), SYMBOL (C++ identifier).
file(READ "${SPV}" hex HEX)
string(LENGTH "${hex}" hexLength)
math(EXPR remainder "${hexLength} % 8")
if(hexLength EQUAL 0 OR NOT remainder EQUAL 0)
  message(FATAL_ERROR "${SPV} is not a SPIR-V binary (size not a multiple of 4 bytes)")
endif()
# SPIR-V words are little-endian: bytes b0 b1 b2 b3 form 0xb3b2b1b0.
string(REGEX REPLACE "(..)(..)(..)(..)" "0x\\4\\3\\2\\1u," words "${hex}")
string(REGEX REPLACE "((0x[0-9a-f]+u,){8})" "\\1\n  " words "${words}")
file(WRITE "${OUT}.tmp"
  "// Generated from ${SPV} by embed_spirv.cmake; do not edit.\n"
  "#include <cstddef>\n#include <cstdint>\n\n"
  "namespace tessera::gpu::spirv {\n"
  "extern const std::uint32_t ${SYMBOL}[];\n"
  "extern const std::size_t ${SYMBOL}Words;\n"
  "const std::uint32_t ${SYMBOL}[] = {\n  ${words}\n};\n"
  "const std::size_t ${SYMBOL}Words = sizeof(${SYMBOL}) / sizeof(${SYMBOL}[0]);\n"
  "}  // namespace tessera::gpu::spirv\n")
file(COPY_FILE "${OUT}.tmp" "${OUT}" ONLY_IF_DIFFERENT)
file(REMOVE "${OUT}.tmp")
