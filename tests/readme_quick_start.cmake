# The README's quick start is examples/quick_start.cpp, byte for byte (the build compiles the
# example, so the code the README shows compiles as written). Takes the first ```cpp block after
# the "## Quick start" heading of README and compares it with EXAMPLE; on a difference it names
# the first line that differs and fails.
#   cmake -DREADME=README.md -DEXAMPLE=examples/quick_start.cpp -P tests/readme_quick_start.cmake
cmake_minimum_required(VERSION 3.21)

foreach(var README EXAMPLE)
  if(NOT DEFINED ${var} OR NOT EXISTS "${${var}}")
    message(FATAL_ERROR "readme_quick_start: -D${var}=<file> must name an existing file (got '${${var}}')")
  endif()
endforeach()

file(READ "${README}" readme)
file(READ "${EXAMPLE}" example)

# The heading, at the start of a line.
set(heading "## Quick start\n")
string(FIND "${readme}" "\n${heading}" at)
if(at EQUAL -1)
  message(FATAL_ERROR "${README} has no line '## Quick start': the quick start must stay under that heading")
endif()
string(LENGTH "\n${heading}" skip)
math(EXPR at "${at} + ${skip}")
string(SUBSTRING "${readme}" ${at} -1 rest)

# The first ```cpp fence after it, at the start of a line.
string(FIND "${rest}" "\n```cpp\n" open)
if(open EQUAL -1)
  message(FATAL_ERROR "${README}: no ```cpp block after '## Quick start'")
endif()
math(EXPR open "${open} + 8")  # past "\n```cpp\n"
string(SUBSTRING "${rest}" ${open} -1 rest)

# Its closing fence: the block is everything up to and including the newline before it.
string(FIND "${rest}" "\n```" close)
if(close EQUAL -1)
  message(FATAL_ERROR "${README}: the ```cpp block after '## Quick start' is not closed")
endif()
math(EXPR close "${close} + 1")
string(SUBSTRING "${rest}" 0 ${close} block)

if("${block}" STREQUAL "${example}")
  return()
endif()

# Name the first differing line.
set(a "${block}")
set(b "${example}")
set(line 1)
while(TRUE)
  string(FIND "${a}" "\n" na)
  string(FIND "${b}" "\n" nb)
  if(na EQUAL -1)
    set(la "${a}")
  else()
    string(SUBSTRING "${a}" 0 ${na} la)
  endif()
  if(nb EQUAL -1)
    set(lb "${b}")
  else()
    string(SUBSTRING "${b}" 0 ${nb} lb)
  endif()
  if(NOT "${la}" STREQUAL "${lb}" OR na EQUAL -1 OR nb EQUAL -1)
    break()
  endif()
  math(EXPR na "${na} + 1")
  math(EXPR nb "${nb} + 1")
  string(SUBSTRING "${a}" ${na} -1 a)
  string(SUBSTRING "${b}" ${nb} -1 b)
  math(EXPR line "${line} + 1")
endwhile()
if("${la}" STREQUAL "${lb}")
  # One text is the other plus more at its end (an extra line or newline): show what is left.
  string(REPLACE "\n" "\\n" la "${a}")
  string(REPLACE "\n" "\\n" lb "${b}")
  set(what "they agree to line ${line} of the example, then one ends before the other; what is left")
else()
  set(what "they first differ at line ${line} of the example")
endif()
message(FATAL_ERROR
  "The README's quick start (the first ```cpp block after '## Quick start' in ${README}) is not "
  "${EXAMPLE} byte for byte: ${what}:\n"
  "  README:  '${la}'\n"
  "  example: '${lb}'\n"
  "Copy the example into the README's block (or the block into the example) so that they are one text.")
