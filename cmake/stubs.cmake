# The type stubs of hovi._core and hovi._baselines (included by CMakeLists.txt when HOVI_STUBS is ON).
#
# After the extensions link, they are copied into a staging package (an empty hovi/__init__.py beside
# them, so that only the extensions are imported) and scripts/stubgen.py runs pybind11-stubgen on
# them; the stubs (hovi/_core/__init__.pyi, trajopt.pyi; hovi/_baselines.pyi) are installed next to
# the modules.
# scikit-build-core lets installed files take precedence over the package's own, so the wheel
# ships these rather than the committed copy in python/hovi/_core/ (which `make stubs` refreshes
# and tests/test_stubs.py compares with them).
execute_process(COMMAND ${Python_EXECUTABLE} -c "import pybind11_stubgen"
                RESULT_VARIABLE HOVI_STUBGEN_MISSING OUTPUT_QUIET ERROR_QUIET)
if(HOVI_STUBGEN_MISSING)
  message(FATAL_ERROR "HOVI_STUBS: pybind11-stubgen is not installed for ${Python_EXECUTABLE}: install it "
                      "(pip install pybind11-stubgen; requirements-dev.txt has it), or configure with "
                      "-DHOVI_STUBS=OFF to ship the committed python/hovi/_core/*.pyi instead")
endif()
set(HOVI_STUB_STAGE ${CMAKE_CURRENT_BINARY_DIR}/stubgen/import)
set(HOVI_STUB_OUT ${CMAKE_CURRENT_BINARY_DIR}/stubgen/out)
file(MAKE_DIRECTORY ${HOVI_STUB_STAGE}/hovi)
if(NOT EXISTS ${HOVI_STUB_STAGE}/hovi/__init__.py)
  file(WRITE ${HOVI_STUB_STAGE}/hovi/__init__.py "")
endif()
set(HOVI_STUB_MODULES _core)
if(TARGET _baselines)
  list(APPEND HOVI_STUB_MODULES _baselines)
endif()
set(HOVI_STUB_COPIES)
foreach(module IN LISTS HOVI_STUB_MODULES)
  list(APPEND HOVI_STUB_COPIES COMMAND ${CMAKE_COMMAND} -E copy $<TARGET_FILE:${module}> ${HOVI_STUB_STAGE}/hovi/)
endforeach()
add_custom_command(
  OUTPUT ${HOVI_STUB_OUT}/hovi/_core/__init__.pyi
  ${HOVI_STUB_COPIES}
  COMMAND ${Python_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/scripts/stubgen.py ${HOVI_STUB_OUT} --path ${HOVI_STUB_STAGE}
  DEPENDS ${HOVI_STUB_MODULES} ${CMAKE_CURRENT_SOURCE_DIR}/scripts/stubgen.py
  COMMENT "Generating the type stubs of hovi._core (pybind11-stubgen)"
  VERBATIM)
add_custom_target(hovi_stubs ALL DEPENDS ${HOVI_STUB_OUT}/hovi/_core/__init__.pyi)
install(DIRECTORY ${HOVI_STUB_OUT}/hovi/_core DESTINATION hovi FILES_MATCHING PATTERN "*.pyi")
if(TARGET _baselines)
  install(FILES ${HOVI_STUB_OUT}/hovi/_baselines.pyi DESTINATION hovi)
endif()
