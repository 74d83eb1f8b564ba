# The type stubs of hovi._core (included by CMakeLists.txt when HOVI_STUBS is ON).
#
# After _core links, it is copied into a staging package (an empty hovi/__init__.py beside it, so
# that only the extension is imported) and scripts/stubgen.py runs pybind11-stubgen on it; the
# stubs (hovi/_core/__init__.pyi, baselines.pyi, trajopt.pyi) are installed next to the module.
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
add_custom_command(
  OUTPUT ${HOVI_STUB_OUT}/hovi/_core/__init__.pyi
  COMMAND ${CMAKE_COMMAND} -E copy $<TARGET_FILE:_core> ${HOVI_STUB_STAGE}/hovi/
  COMMAND ${Python_EXECUTABLE} ${CMAKE_CURRENT_SOURCE_DIR}/scripts/stubgen.py ${HOVI_STUB_OUT} --path ${HOVI_STUB_STAGE}
  DEPENDS _core ${CMAKE_CURRENT_SOURCE_DIR}/scripts/stubgen.py
  COMMENT "Generating the type stubs of hovi._core (pybind11-stubgen)"
  VERBATIM)
add_custom_target(hovi_stubs ALL DEPENDS ${HOVI_STUB_OUT}/hovi/_core/__init__.pyi)
install(DIRECTORY ${HOVI_STUB_OUT}/hovi/_core DESTINATION hovi FILES_MATCHING PATTERN "*.pyi")
