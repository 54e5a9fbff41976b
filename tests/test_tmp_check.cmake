# The temporary directory of a test run: emptied before the tests (MODE=setup), and checked
# to be empty after them (MODE=check), naming whatever a test left behind.
if(MODE STREQUAL "setup")
  file(REMOVE_RECURSE ${DIR})
  file(MAKE_DIRECTORY ${DIR})
elseif(MODE STREQUAL "check")
  file(GLOB leftovers LIST_DIRECTORIES true ${DIR}/*)
  if(leftovers)
    string(REPLACE ";" "\n  " list "${leftovers}")
    message(FATAL_ERROR "tests left files in the temporary directory:\n  ${list}")
  endif()
else()
  message(FATAL_ERROR "MODE must be setup or check")
endif()
