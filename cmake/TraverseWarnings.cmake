# Project code compiles warning-free under -Wall -Wextra; third-party headers are SYSTEM.
add_library(traverse_warnings INTERFACE)
target_compile_options(traverse_warnings INTERFACE -Wall -Wextra)
if(TRAVERSE_SANITIZE)
  target_compile_options(traverse_warnings INTERFACE -fsanitize=address,undefined -fno-omit-frame-pointer)
  target_link_options(traverse_warnings INTERFACE -fsanitize=address,undefined)
endif()
