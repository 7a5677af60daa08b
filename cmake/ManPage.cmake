# cmake -P script: writes the man page shellcontract.1 from the CLI's own help, so that the page
# cannot drift from the tool: `shellcontract --help` is the DESCRIPTION, and each command its
# list names ("run", "bench ccd", ...) gets a section with its `--help`. Run at build time by
# cmake/ShellContractManPage.cmake; tests/docs/man_page_test.py checks the result.
#   cmake -DCLI=build/shellcontract -DOUT=shellcontract.1 -DTITLE="ShellContract 0.2.0"
#         -DDESCRIPTION="..." [-DOPTIONAL_COMMANDS=sweep] -P cmake/ManPage.cmake
# OPTIONAL_COMMANDS: commands whose --help may fail (sweep, whose help is the Python package's, in
# a build without the Python module); their section then says so.
#
# The help texts follow two layouts, which become roff as follows (anything else is kept as it is,
# in no-fill mode):
#   - a line at column 0 ending in ':' (or "options") above indented lines: a bold heading;
#   - lines at column 0, with lines indented deeper than 2 under them (a hanging indent, as in
#     "exit codes: ..."): a paragraph, filled;
#   - lines indented by 2 that start with '-' or hold a gap of 2 spaces ("  -o [ --output ] FILE
#     output mesh", "  run INPUT ...   contract ..."), each with the deeper lines under it: a
#     tagged paragraph (.TP), the part before the gap in bold.
cmake_minimum_required(VERSION 3.20)
foreach(v CLI OUT TITLE DESCRIPTION)
  if(NOT DEFINED ${v})
    message(FATAL_ERROR "ManPage.cmake: -D${v}=... is required")
  endif()
endforeach()

# A CMake list cannot hold ';', '[', ']' or a '\' before a separator as they are: each is a
# placeholder until the page is written ('\' then as roff's \e).
function(protect text out)
  string(REPLACE "\\" "@SC_BS@" text "${text}")
  string(REPLACE ";" "@SC_SC@" text "${text}")
  string(REPLACE "[" "@SC_LB@" text "${text}")
  string(REPLACE "]" "@SC_RB@" text "${text}")
  set(${out} "${text}" PARENT_SCOPE)
endfunction()

function(restore text out)
  string(REPLACE "@SC_SC@" ";" text "${text}")
  string(REPLACE "@SC_LB@" "[" text "${text}")
  string(REPLACE "@SC_RB@" "]" text "${text}")
  string(REPLACE "@SC_BS@" "\\" text "${text}")
  set(${out} "${text}" PARENT_SCOPE)
endfunction()

# `CLI WORDS --help` as a list of lines (placeholders in); rc is its exit code. Fixed width and
# locale: argparse (sweep) wraps at the terminal's width.
function(help_lines out rc_out)
  execute_process(COMMAND ${CMAKE_COMMAND} -E env COLUMNS=80 LC_ALL=C ${CLI} ${ARGN} --help
                  RESULT_VARIABLE rc OUTPUT_VARIABLE text ERROR_VARIABLE err)
  set(${rc_out} "${rc}" PARENT_SCOPE)
  if(NOT rc EQUAL 0)
    protect("${err}" err)
    set(${out} "${err}" PARENT_SCOPE)
    return()
  endif()
  string(REGEX REPLACE "\n+$" "" text "${text}")
  protect("${text}" text)
  string(REPLACE "\n" ";" text "${text}")
  set(${out} "${text}" PARENT_SCOPE)
endfunction()

# Text as a roff text line: '\' printed as itself, '-' a minus (so that options copy and search
# as typed, and no line breaks inside one), and \& first so that a leading '.' or ''' is text.
function(roff_text text out)
  string(REPLACE "@SC_BS@" "\\e" text "${text}")
  string(REPLACE "-" "\\-" text "${text}")
  set(${out} "\\&${text}" PARENT_SCOPE)
endfunction()

function(indent_of line out)
  set(n 0)
  if(line MATCHES "^( +)")
    string(LENGTH "${CMAKE_MATCH_1}" n)
  endif()
  set(${out} ${n} PARENT_SCOPE)
endfunction()

# A tagged line: indented by 2, then an option ('-') or a term and a gap of 2 spaces. Sets
# <out>_tag and <out>_text (the part after the gap, possibly empty); <out> is FALSE otherwise.
function(split_tagged line out)
  set(${out} FALSE PARENT_SCOPE)
  indent_of("${line}" n)
  if(NOT n EQUAL 2)
    return()
  endif()
  string(SUBSTRING "${line}" 2 -1 rest)
  string(FIND "${rest}" "  " gap)
  if(gap LESS 0 AND NOT rest MATCHES "^-")
    return()
  endif()
  if(gap LESS 0)
    set(tag "${rest}")
    set(text "")
  else()
    string(SUBSTRING "${rest}" 0 ${gap} tag)
    string(SUBSTRING "${rest}" ${gap} -1 text)
    string(STRIP "${text}" text)
  endif()
  set(${out} TRUE PARENT_SCOPE)
  set(${out}_tag "${tag}" PARENT_SCOPE)
  set(${out}_text "${text}" PARENT_SCOPE)
endfunction()

# One help text (a list of lines) as roff, appended to the variable named by out.
function(help_to_roff lines out)
  set(roff "${${out}}")
  list(LENGTH lines n)
  set(i 0)
  while(i LESS n)
    list(GET lines ${i} line)
    if(line STREQUAL "")
      math(EXPR i "${i} + 1")
      continue()
    endif()
    indent_of("${line}" indent)
    set(next_indent -1)
    math(EXPR j "${i} + 1")
    if(j LESS n)
      list(GET lines ${j} next)
      if(NOT next STREQUAL "")
        indent_of("${next}" next_indent)
      endif()
    endif()
    string(LENGTH "${line}" length)
    if(indent EQUAL 0 AND next_indent EQUAL 2 AND
       ((line MATCHES ":$" AND length LESS_EQUAL 50) OR line STREQUAL "options"))
      roff_text("${line}" t)
      string(APPEND roff ".PP\n\\fB${t}\\fR\n")
      set(i ${j})
    elseif(indent EQUAL 0)
      # A paragraph: lines at column 0 and a hanging indent of one depth under them.
      string(APPEND roff ".PP\n")
      set(hang -1)
      while(TRUE)
        string(STRIP "${line}" stripped)
        roff_text("${stripped}" t)
        string(APPEND roff "${t}\n")
        math(EXPR i "${i} + 1")
        if(NOT i LESS n)
          break()
        endif()
        list(GET lines ${i} line)
        if(line STREQUAL "")
          break()
        endif()
        indent_of("${line}" k)
        if(k EQUAL 0)
          continue()
        elseif(k GREATER 2 AND (hang EQUAL -1 OR hang EQUAL k))
          set(hang ${k})
        else()
          break()
        endif()
      endwhile()
    else()
      # An indented block, up to a blank line or a line at column 0: tagged paragraphs if every
      # line is a tagged line or deeper under one, else kept as it is.
      set(block "")
      set(tagged TRUE)
      while(i LESS n)
        list(GET lines ${i} line)
        indent_of("${line}" k)
        if(line STREQUAL "" OR k EQUAL 0)
          break()
        endif()
        split_tagged("${line}" entry)
        if(NOT entry AND (k LESS_EQUAL 2 OR block STREQUAL ""))
          set(tagged FALSE)
        endif()
        list(APPEND block "${line}")
        math(EXPR i "${i} + 1")
      endwhile()
      if(tagged)
        foreach(line IN LISTS block)
          split_tagged("${line}" entry)
          if(entry)
            roff_text("${entry_tag}" t)
            string(APPEND roff ".TP\n\\fB${t}\\fR\n")
            set(line "${entry_text}")
          endif()
          string(STRIP "${line}" stripped)
          if(NOT stripped STREQUAL "")
            roff_text("${stripped}" t)
            string(APPEND roff "${t}\n")
          endif()
        endforeach()
      else()
        string(APPEND roff ".PP\n.nf\n")
        foreach(line IN LISTS block)
          roff_text("${line}" t)
          string(APPEND roff "${t}\n")
        endforeach()
        string(APPEND roff ".fi\n")
      endif()
    endif()
  endwhile()
  set(${out} "${roff}" PARENT_SCOPE)
endfunction()

help_lines(main rc)
if(NOT rc EQUAL 0)
  restore("${main}" main)
  message(FATAL_ERROR "${CLI} --help failed (${rc}): ${main}")
endif()
# The commands: the leading lower-case words of each line of the list under "commands:".
set(commands "")
set(in_list FALSE)
foreach(line IN LISTS main)
  if(line STREQUAL "commands:")
    set(in_list TRUE)
  elseif(line STREQUAL "")
    set(in_list FALSE)
  elseif(in_list AND line MATCHES "^  ([a-z]+( [a-z]+)*)( |$)")
    list(APPEND commands "${CMAKE_MATCH_1}")
  endif()
endforeach()
if(NOT commands)
  message(FATAL_ERROR "${CLI} --help lists no commands under 'commands:'")
endif()

roff_text("${DESCRIPTION}" description)
string(REPLACE "\"" "" title "${TITLE}")
set(page ".\\\" Generated from the CLI's --help by cmake/ManPage.cmake: edit the help, not this file.
.TH SHELLCONTRACT 1 \"\" \"${title}\" \"User Commands\"
.nh
.ad l
.SH NAME
shellcontract \\- ${description}
.SH SYNOPSIS
\\fBshellcontract\\fR \\fIcommand\\fR [\\fIoptions\\fR]
.SH DESCRIPTION
")
help_to_roff("${main}" page)
string(APPEND page ".SH COMMANDS\n")
foreach(command IN LISTS commands)
  string(APPEND page ".SS \"shellcontract ${command}\"\n")
  string(REPLACE " " ";" words "${command}")
  help_lines(text rc ${words})
  if(rc EQUAL 0)
    help_to_roff("${text}" page)
  elseif(command IN_LIST OPTIONAL_COMMANDS)
    # Said without the error itself, which names this build's folders.
    set(t "'shellcontract ${command} --help' did not run where this page was made (a build")
    string(APPEND t " without the Python module); its options are in that help where it runs.")
    roff_text("${t}" t)
    string(APPEND page ".PP\n${t}\n")
  else()
    restore("${text}" text)
    message(FATAL_ERROR "${CLI} ${command} --help failed (${rc}): ${text}")
  endif()
endforeach()

restore("${page}" page)
# Written whole or not at all: a failed run leaves no page that the build takes for made.
file(WRITE ${OUT}.tmp "${page}")
file(RENAME ${OUT}.tmp ${OUT})
