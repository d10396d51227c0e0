# SPDX-License-Identifier: MIT
# CMMCOMP_SANITIZERS (a list such as "address;undefined") applies to every target built here,
# so that test executables and the libraries they link agree on the runtime.
if(CMMCOMP_SANITIZERS)
  list(JOIN CMMCOMP_SANITIZERS "," _cmmcomp_san)
  add_compile_options(-fsanitize=${_cmmcomp_san} -fno-omit-frame-pointer -fno-sanitize-recover=all)
  add_link_options(-fsanitize=${_cmmcomp_san})
endif()
