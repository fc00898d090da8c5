# The man page: help2man on `framepass --help`, plus a COMMANDS section made here from each
# subcommand's --help and the checked-in framepass.h2m (EXIT STATUS, ENVIRONMENT, EXAMPLES).
# help2man runs the program in the C locale unless told otherwise, and the help text is UTF-8
# (an em dash, ×, ←): under C each of those bytes would read '?'. So: C.UTF-8.
#
#   cmake -DFRAMEPASS=exe -DHELP2MAN=help2man -DINCLUDE=framepass.h2m -DOUTPUT=framepass.1
#         -P ManPage.cmake
foreach(var FRAMEPASS HELP2MAN INCLUDE OUTPUT)
    if(NOT DEFINED ${var})
        message(FATAL_ERROR "ManPage.cmake: -D${var}=... is required")
    endif()
endforeach()
set(ENV{LC_ALL} C.UTF-8)

function(help_of out)
    execute_process(COMMAND ${FRAMEPASS} ${ARGN} --help
                    OUTPUT_VARIABLE text RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "framepass ${ARGN} --help failed (${rc})")
    endif()
    set(${out} "${text}" PARENT_SCOPE)
endfunction()

help_of(top)
string(FIND "${top}" "Subcommands:" at)
if(at EQUAL -1)
    message(FATAL_ERROR "framepass --help lists no subcommands")
endif()
string(SUBSTRING "${top}" ${at} -1 listing)
string(REGEX MATCHALL "\n  [a-z][a-z0-9-]*" names "${listing}")

set(commands "[COMMANDS]\n")
foreach(name IN LISTS names)
    string(STRIP "${name}" name)
    help_of(text ${name})
    string(STRIP "${text}" text)
    string(REPLACE "${FRAMEPASS}" "framepass" text "${text}")  # CLI11's usage line names argv[0]
    # As roff, verbatim: backslashes escaped, '-' a minus sign (options copy and paste), and no
    # line that starts a request (. or ') or that help2man reads as a section of its own ([X]).
    string(REPLACE "\\" "\\e" text "${text}")
    string(REPLACE "-" "\\-" text "${text}")
    string(REGEX REPLACE "\n([.'[/])" "\n\\\\&\\1" text "\n${text}")
    string(SUBSTRING "${text}" 1 -1 text)
    string(APPEND commands ".SS \"framepass ${name}\"\n.nf\n${text}\n.fi\n")
endforeach()
get_filename_component(dir "${OUTPUT}" DIRECTORY)
file(WRITE "${dir}/framepass-commands.h2m" "${commands}")

execute_process(
    COMMAND ${HELP2MAN} --no-info --no-discard-stderr --locale=C.UTF-8
            --name "re-run Unreal Engine lighting passes on captured GBuffers"
            --include "${dir}/framepass-commands.h2m" --include "${INCLUDE}"
            --output "${OUTPUT}" "${FRAMEPASS}"
    RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "help2man failed (${rc})")
endif()
file(READ "${OUTPUT}" page)
if(page MATCHES "\\?\\?\\?")
    file(REMOVE "${OUTPUT}")
    message(FATAL_ERROR "${OUTPUT} reads '???': help2man decoded UTF-8 help text in another locale")
endif()
