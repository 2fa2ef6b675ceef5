# Writes the linker version script of libadem.so: the functions the public headers declare
# (include/adem/*.h) are global, every other symbol is local.
#   cmake -DOUT=adem.map -DDIR=include/adem -P exports.cmake
file(GLOB headers ${DIR}/*.h)
set(names "")
foreach(h ${headers})
  file(READ ${h} text)
  # comments may name functions they do not declare: drop them first
  string(REGEX REPLACE "/\\*([^*]|\\*+[^*/])*\\*+/" "" text "${text}")
  string(REGEX MATCHALL "adem_[a-z0-9_]+[ ]*\\(" found "${text}")
  foreach(f ${found})
    string(REGEX REPLACE "[ ]*\\($" "" f "${f}")
    list(APPEND names ${f})
  endforeach()
endforeach()
list(REMOVE_DUPLICATES names)
list(SORT names)
set(body "{\n  global:\n")
foreach(f ${names})
  string(APPEND body "    ${f};\n")
endforeach()
string(APPEND body "  local:\n    *;\n};\n")
file(WRITE ${OUT}.tmp "${body}")
file(COPY_FILE ${OUT}.tmp ${OUT} ONLY_IF_DIFFERENT)
