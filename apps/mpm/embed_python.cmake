# Writes embedded_python.hpp: every python/*.py helper as a string, so the installed program needs no
# separate script files. Run at build time with -DOUT=... -DSOURCES="a.py;b.py".
set(body "")
set(table "")
foreach(src IN LISTS SOURCES)
  get_filename_component(name ${src} NAME_WE)
  file(READ ${src} text)
  string(APPEND body "inline constexpr std::string_view ${name}_py = R\"mpm_py(${text})mpm_py\";\n")
  string(APPEND table "    EmbeddedScript{\"${name}\", ${name}_py},\n")
endforeach()
file(WRITE ${OUT}.tmp "#pragma once\n// Generated from apps/mpm/python/*.py by embed_python.cmake; do not edit.\n"
  "#include <array>\n#include <string_view>\n\nnamespace mpm::app {\n\n"
  "struct EmbeddedScript {\n  std::string_view name, text;\n};\n\n${body}\n"
  "inline constexpr std::array embedded_scripts{\n${table}};\n\n}  // namespace mpm::app\n")
file(COPY_FILE ${OUT}.tmp ${OUT} ONLY_IF_DIFFERENT)
