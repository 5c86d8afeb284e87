# MOPAD_SANITIZE: the whole project (libraries, tools, tests) built with GCC's sanitizers, in a
# build folder of its own (scripts/sanitize.sh; docs/reliability.md, "Sanitizers"):
#   address  AddressSanitizer (with LeakSanitizer) and UndefinedBehaviorSanitizer, plus the
#            float-to-integer overflow check that -fsanitize=undefined leaves out in GCC (a NaN or
#            out-of-range double cast to a grid index); every UB report aborts (no recovery)
#   thread   ThreadSanitizer
# Empty (the default): no sanitizer. The flags go to compiling and linking alike, so every
# object and executable carries the same runtime.
set(MOPAD_SANITIZE "" CACHE STRING "Sanitizers: '' (none), 'address' (ASan+LSan+UBSan) or 'thread' (TSan)")
set_property(CACHE MOPAD_SANITIZE PROPERTY STRINGS "" address thread)
if(MOPAD_SANITIZE STREQUAL "address")
  set(mopad_sanitize_flags -fsanitize=address,undefined,float-cast-overflow
      -fno-sanitize-recover=undefined,float-cast-overflow -fno-omit-frame-pointer)
elseif(MOPAD_SANITIZE STREQUAL "thread")
  set(mopad_sanitize_flags -fsanitize=thread -fno-omit-frame-pointer)
elseif(NOT MOPAD_SANITIZE STREQUAL "")
  message(FATAL_ERROR "MOPAD_SANITIZE: unknown value '${MOPAD_SANITIZE}'; expected '', address or thread")
endif()
if(mopad_sanitize_flags)
  add_compile_options(${mopad_sanitize_flags})
  add_link_options(${mopad_sanitize_flags})
endif()
