# Doxygen input filter for the hairscatter headers (see Doxyfile.in): the headers use plain
# // comments, which Doxygen ignores. This makes them documentation without editing them.
#
# Line 1 is "// hairscatter — <what the header holds>": the file's description.
1s#^// hairscatter — \(.*\)$#/// @file\n/// \1#
# A comment on a line of its own documents what follows it.
s#^\([[:space:]]*\)//\([[:space:]]\|$\)#\1///\2#
# A comment after a member on the same line documents that member (members sit at one
# level of indentation; deeper lines are function bodies, whose comments stay plain).
s#^\(    [^[:space:]/].*[;,{]\)\([[:space:]]\+\)//[[:space:]]#\1\2///< #
