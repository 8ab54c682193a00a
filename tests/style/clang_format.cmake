# Fails when a tracked C++ file differs from what clang-format makes of it under the checked-in
# .clang-format. Run by CTest as Style.ClangFormat; CLANG_FORMAT and SOURCE_DIR come from there.
# The files are the tracked ones (git ls-files), so a build tree or a scratch file is not read.
find_package(Git REQUIRED)
execute_process(COMMAND ${GIT_EXECUTABLE} ls-files -- *.cpp *.hpp *.h
                WORKING_DIRECTORY ${SOURCE_DIR} OUTPUT_VARIABLE files RESULT_VARIABLE rc
                OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT rc EQUAL 0 OR files STREQUAL "")
  message(FATAL_ERROR "style: git ls-files found no C++ files in ${SOURCE_DIR}")
endif()
string(REPLACE "\n" ";" files "${files}")
list(LENGTH files count)
execute_process(COMMAND ${CLANG_FORMAT} --dry-run -Werror ${files}
                WORKING_DIRECTORY ${SOURCE_DIR} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "style: files above differ from .clang-format; run: "
                      "git ls-files '*.cpp' '*.hpp' '*.h' | xargs clang-format-14 -i")
endif()
message(STATUS "style: ${count} files as .clang-format writes them")
