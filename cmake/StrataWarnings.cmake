# Warnings for Strata's own targets only (third-party headers are included as SYSTEM by their packages).
add_library(strata_warnings INTERFACE)
target_compile_options(strata_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion -Wnon-virtual-dtor
  -Wold-style-cast -Woverloaded-virtual -Wdouble-promotion -Wformat=2
  -Wimplicit-fallthrough
  # C++20 designated initializers leave defaulted members out on purpose; GCC 12 warns about that.
  -Wno-missing-field-initializers)
