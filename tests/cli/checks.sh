# The helpers every CLI test script sources: `check` runs a command and counts it, `expect_exit`
# asserts an exit code and a word of the message, `finish` prints the count and fails if any did.
# The sourcing script sets DIR (its scratch folder) first.
passed=0; failed=0
check() {  # check NAME COMMAND...
    local name="$1"; shift
    if "$@" >"$DIR/last.log" 2>&1; then passed=$((passed + 1)); echo "ok   $name"
    else failed=$((failed + 1)); echo "FAIL $name"; sed 's/^/     /' "$DIR/last.log" | tail -20; fi
}
expect_exit() {  # expect_exit CODE PATTERN COMMAND...
    local code="$1" pattern="$2"; shift 2
    "$@" >"$DIR/out.log" 2>&1; local got=$?
    [ "$got" = "$code" ] || { echo "exit $got, expected $code"; cat "$DIR/out.log"; return 1; }
    grep -qF -- "$pattern" "$DIR/out.log" || { echo "missing: $pattern"; cat "$DIR/out.log"; return 1; }
}
finish() {
    echo "$passed passed, $failed failed"
    [ "$failed" = 0 ]
}
