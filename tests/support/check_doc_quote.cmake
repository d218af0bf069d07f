# Fails unless a page's code block that begins with a given line is quoted verbatim from a
# source file, so that a snippet shown on a page is code that is compiled (the reverse of
# check_doc_example.cmake, which checks that a whole program is on its page).
#   cmake -DDOC=<page.md> -DSOURCE=<file> -DFIRST_LINE=<the block's first line> -P check_doc_quote.cmake
if(NOT DOC OR NOT SOURCE OR NOT FIRST_LINE)
  message(FATAL_ERROR "usage: cmake -DDOC=<page.md> -DSOURCE=<file> -DFIRST_LINE=<line> -P check_doc_quote.cmake")
endif()
file(READ "${DOC}" doc)
file(READ "${SOURCE}" source)
get_filename_component(doc_name "${DOC}" NAME)
get_filename_component(source_name "${SOURCE}" NAME)
string(FIND "${doc}" "```cpp\n${FIRST_LINE}" start)
if(start EQUAL -1)
  message(FATAL_ERROR "${doc_name} has no cpp code block beginning \"${FIRST_LINE}\"")
endif()
math(EXPR start "${start} + 7")  # past ```cpp and its newline
string(SUBSTRING "${doc}" ${start} -1 rest)
string(FIND "${rest}" "\n```" end)
string(SUBSTRING "${rest}" 0 ${end} block)
string(FIND "${source}" "${block}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "${doc_name}'s block beginning \"${FIRST_LINE}\" is not in ${source_name} verbatim: "
                      "update the page")
endif()
message(STATUS "${doc_name}: the block beginning \"${FIRST_LINE}\" is ${source_name}'s")
