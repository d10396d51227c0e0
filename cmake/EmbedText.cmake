# SPDX-License-Identifier: MIT
# cmake -DINPUT=file -DOUTPUT=file.inc -DNAME=kSymbol -P EmbedText.cmake
# Writes `constexpr const char NAME[] = R"...(<file>)...";` so a data file is compiled in.
file(READ "${INPUT}" content)
set(delim "cmmcomp_embed")
file(WRITE "${OUTPUT}.tmp" "// Generated from ${INPUT}; do not edit.\nconstexpr const char ${NAME}[] = R\"${delim}(${content})${delim}\";\n")
file(COPY_FILE "${OUTPUT}.tmp" "${OUTPUT}" ONLY_IF_DIFFERENT)
