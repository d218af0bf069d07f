# Fails unless README.md quotes tests/readme_example.cpp verbatim, so the usage example a
# reader copies is the one the tests compile and run.
#   cmake -DREADME=<README.md> -DEXAMPLE=<readme_example.cpp> -P check_readme_example.cmake
file(READ "${README}" readme)
file(READ "${EXAMPLE}" example)
string(STRIP "${example}" example)
string(FIND "${readme}" "${example}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "README.md does not contain tests/readme_example.cpp verbatim: update the README's usage example")
endif()
message(STATUS "README.md quotes tests/readme_example.cpp verbatim")
