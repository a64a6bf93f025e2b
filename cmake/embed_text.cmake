# Writes OUTPUT, a C++ file defining `const char* const vocal::NAME` with the text of INPUT.
file(READ "${INPUT}" content)
file(WRITE "${OUTPUT}" "// Generated from ${INPUT}: do not edit.\nnamespace vocal {\nextern const char* const ${NAME};\nconst char* const ${NAME} = R\"VOCAL_EMBEDDED(${content})VOCAL_EMBEDDED\";\n}  // namespace vocal\n")
