# docs/integration.md shows each docs/examples/*.c file verbatim (the test suite compiles and runs
# those files): fails naming the example the guide no longer matches. Run with cmake -P and
# -DGUIDE=docs/integration.md -DEXAMPLES=docs/examples.
file(READ ${GUIDE} guide)
file(GLOB examples ${EXAMPLES}/*.c)
list(LENGTH examples count)
if(count EQUAL 0)
    message(FATAL_ERROR "no examples in ${EXAMPLES}")
endif()
foreach(example ${examples})
    file(READ ${example} text)
    string(STRIP "${text}" text)
    string(FIND "${guide}" "```c\n${text}\n```" at)
    if(at EQUAL -1)
        message(FATAL_ERROR "${GUIDE} does not show ${example} as it is: copy the file into its "
                            "```c block")
    endif()
endforeach()
message(STATUS "${GUIDE} shows all ${count} examples as they are")
