#!/usr/bin/env bash
# Farm behaviour of `framepass run`: --continue-on-error, --skip-existing, the report written
# whatever happens, kill -9 leaving only whole files at final names and a rerun cleaning the
# temporaries, and no command writing over its inputs. Usage: farm_test.sh FRAMEPASS SOURCE_DIR SCRATCH
set -u
source "$(cd "$(dirname "$0")" && pwd)/checks.sh"
FP="$1"; SRC="$2"; DIR="$3/farm"
rm -rf "$DIR"; mkdir -p "$DIR"; DIR="$(cd "$DIR" && pwd)"; cd "$DIR"

check "capture a 6-frame sequence" "$FP" capture "$SRC/examples/cornell/scene.json" -o seq.####.exr --frames 1-6 --width 64 --height 64
echo '{ "version": 1, "capture": "seq.####.exr", "frames": "1-6" }' > seq.json
check "a clean sequential run" "$FP" run seq.json -o clean
check "reading each frame at its start (--no-read-ahead) gives the same files, byte for byte" bash -c "
    '$FP' run seq.json -o inplace --no-read-ahead > /dev/null &&
    for f in 1 3 6; do for o in ssgi indirect; do cmp clean/\$o.000\$f.exr inplace/\$o.000\$f.exr || exit 1; done; done"

# A bad frame in the middle.
mkdir -p broken && cp seq.0*.exr broken/ && head -c 3000 seq.0003.exr > broken/seq.0003.exr
echo '{ "version": 1, "capture": "broken/seq.####.exr", "frames": "1-6" }' > broken.json
check "without --continue-on-error the run stops at the bad frame, exit 1, report still written" bash -c "
    '$FP' run broken.json -o stop --report stop.json > stop.log 2>&1; [ \$? = 1 ] &&
    python3 -c '
import json; r = json.load(open(\"stop.json\")); s = [f[\"status\"] for f in r[\"frames\"]]
assert s == [\"ok\", \"ok\", \"failed\"], s
assert \"seq.0003.exr\" in r[\"frames\"][2][\"error\"]' && test ! -e stop/ssgi.0004.exr"
check "--continue-on-error attempts every frame and lists the failed ones, exit 1" bash -c "
    '$FP' run broken.json -o cont --report cont.json --continue-on-error > cont.log 2>&1; [ \$? = 1 ] &&
    grep -q '1 of 6 frame(s) failed: 3' cont.log && test -f cont/ssgi.0006.exr && test ! -e cont/ssgi.0003.exr &&
    python3 -c '
import json; r = json.load(open(\"cont.json\")); s = [f[\"status\"] for f in r[\"frames\"]]
assert s == [\"ok\", \"ok\", \"failed\", \"ok\", \"ok\", \"ok\"], s
assert r[\"failedFrames\"] == [3]'"
check "the frames before the bad one equal the clean run's" bash -c "cmp clean/ssgi.0002.exr cont/ssgi.0002.exr && cmp clean/indirect.0002.exr cont/indirect.0002.exr"

# A re-queued task: the first half is done; the rest is computed with the history of a
# sequential run (the skipped frames run again, writing nothing, since SSGI's denoiser is temporal).
check "frames 1-3 written" "$FP" run seq.json --frames 1-3 -o requeue
check "--skip-existing computes only frames 4-6" bash -c "'$FP' run seq.json -o requeue --skip-existing --report rq.json > rq.log 2>&1 &&
    grep -q 'frame 2: every output exists, run for history only' rq.log && ! grep -q 'wrote requeue/ssgi.0002.exr' rq.log && grep -q 'wrote requeue/ssgi.0005.exr' rq.log"
check "and writes the same bytes as the sequential run" diff -r clean requeue
check "a run with every output on disk skips every frame" bash -c "'$FP' run seq.json -o requeue --skip-existing --report all.json > /dev/null 2>&1 &&
    python3 -c '
import json; r = json.load(open(\"all.json\")); assert all(f[\"status\"] == \"skipped\" for f in r[\"frames\"]), r[\"frames\"]'"

# kill -9 in the middle of a run: every file at a final name is whole; a rerun finishes the job,
# removes the temporaries the dead process left, and gives the clean run's bytes.
check "capture a heavier 6-frame sequence" "$FP" capture "$SRC/examples/cornell/scene.json" -o big.####.exr --frames 1-6 --width 160 --height 160
echo '{ "version": 1, "capture": "big.####.exr", "frames": "1-6" }' > big.json
check "its clean run" "$FP" --threads 2 run big.json -o big_clean --dump all --report big_clean.json
check "the report gives each frame's stages and the run's frame rate and bound" python3 -c "
import json; r = json.load(open('big_clean.json'))
stages = ['read', 'decode', 'upload', 'pass', 'download', 'encode', 'write']
for f in r['frames']:
    assert all(f[s + 'Seconds'] >= 0 for s in stages), f
    assert f['decodeSeconds'] > 0 and f['passSeconds'] > 0 and f['encodeSeconds'] > 0, f
t = r['throughput']
assert t['frames'] == 6 and t['framesPerSecond'] > 0 and t['boundBy'] in stages, t
assert t['writers'] == 2 and t['readAhead'] == 1, t  # the defaults on 2 threads"
# The pipeline (files written by a pool of writers while the next frame computes, the next
# capture read ahead) changes no byte: none, one and three writers, with and without read-ahead.
check "0, 1 and 3 writers, with and without read-ahead, write the clean run's bytes" bash -c "
    for w in 0 1 3; do '$FP' run big.json -o w\$w --dump all --writers \$w > /dev/null || exit 1; diff -r big_clean w\$w || exit 1; done
    '$FP' run big.json -o w0n --dump all --writers 0 --no-read-ahead > /dev/null && diff -r big_clean w0n"
# A file that cannot be written (a folder holds its name) fails its frame when the frame is
# settled, after the next one computed: that one's files finish whole, the run ends there.
check "a file that fails to write fails its frame; no temporaries; the report lists it" bash -c "
    mkdir -p wfail/ssgi.0003.exr
    '$FP' run big.json -o wfail --report wfail.json > wfail.log 2>&1; [ \$? = 1 ] &&
    grep -q 'ssgi.0003.exr: exists and is not a regular file' wfail.log && [ -z \"\$(find wfail -name '.*.tmp')\" ] &&
    cmp big_clean/ssgi.0002.exr wfail/ssgi.0002.exr && test ! -e wfail/ssgi.0006.exr &&
    python3 -c '
import json; r = json.load(open(\"wfail.json\")); s = [f[\"status\"] for f in r[\"frames\"]]
assert s[:3] == [\"ok\", \"ok\", \"failed\"] and len(s) <= 4, s'"
check "with --continue-on-error the frames after it are written" bash -c "
    '$FP' run big.json -o wfail --report wfail2.json --continue-on-error > wfail2.log 2>&1; [ \$? = 1 ] &&
    grep -q '1 of 6 frame(s) failed: 3' wfail2.log && cmp big_clean/ssgi.0006.exr wfail/ssgi.0006.exr"
check "kill -9 mid-run leaves only whole files at final names" bash -c "
    '$FP' --threads 1 run big.json -o big_kill --dump all > /dev/null 2>&1 & pid=\$!
    for i in \$(seq 1 600); do [ -e big_kill/ssgi.0002.exr ] && break; sleep 0.05; done
    kill -9 \$pid; wait \$pid 2>/dev/null
    touch big_kill/.final.0004.png.999999999.tmp   # as a dead process would leave it
    n=0; for f in \$(cd big_kill && find . -type f ! -name '.*.tmp'); do cmp -s big_kill/\$f big_clean/\$f || { echo \"\$f differs\"; exit 1; }; n=\$((n+1)); done
    [ \$n -gt 0 ] && [ ! -e big_kill/ssgi.0006.exr ]"
check "the rerun removes the temporaries and matches the clean run" bash -c "
    '$FP' run big.json -o big_kill --dump all --skip-existing 2> rerun.err > /dev/null && grep -q 'temporary file(s) a killed run left' rerun.err &&
    [ -z \"\$(find big_kill -name '.*.tmp')\" ] && diff -r big_clean big_kill"

echo '{ "version": 1, "capture": "seq.0001.exr" }' > one.json

# Two runs into one folder: the second whose frames overlap the first's is refused while the
# first runs; a run of other frames (another chunk of the shot) goes ahead beside it.
check "a second run writing the same frames into the same folder is refused, naming the first" bash -c "
    '$FP' --threads 1 run big.json -o shared --frames 1-4 > /dev/null 2>&1 & pid=\$!
    for i in \$(seq 1 600); do [ -e shared/ssgi.0001.exr ] && break; sleep 0.05; done
    kill -STOP \$pid   # held mid-run, its lock with it, however fast the machine
    '$FP' run big.json -o shared --frames 3-4 > second.log 2>&1; code=\$?
    '$FP' run big.json -o shared --frames 5-6 > other.log 2>&1; other=\$?
    kill -CONT \$pid; wait \$pid; first=\$?
    [ \$code = 2 ] && grep -q \"another framepass run (process \$pid) is writing frame 3 into this folder\" second.log &&
    [ \$other = 0 ] && [ \$first = 0 ]"
check "the two chunks together are the clean run's outputs" bash -c "for f in ssgi indirect; do for n in 1 2 3 4; do cmp big_clean/\$f.000\$n.exr shared/\$f.000\$n.exr || exit 1; done; done"

# SIGTERM (pre-emption) and SIGINT: stop between passes, no temporaries, the report marks the
# interrupted frame, exit 143 / 130.
for sig in TERM INT; do
    code=143; [ $sig = INT ] && code=130
    check "SIG$sig stops the run at a safe point: exit $code, report written, no temporaries" bash -c "
        '$FP' --threads 1 run big.json -o sig$sig --report sig$sig.json > sig$sig.log 2>&1 & pid=\$!
        for i in \$(seq 1 600); do [ -e sig$sig/ssgi.0002.exr ] && break; sleep 0.05; done
        kill -$sig \$pid; wait \$pid; got=\$?
        [ \$got = $code ] && [ -z \"\$(find sig$sig -name '.*.tmp')\" ] && grep -q 'stopped by SIG$sig at a safe point' sig$sig.log &&
        python3 -c '
import json; r = json.load(open(\"sig$sig.json\")); s = [f[\"status\"] for f in r[\"frames\"]]
assert s[-1] == \"interrupted\" and all(x == \"ok\" for x in s[:-1]) and len(s) < 6, s
assert r[\"interrupted\"][\"frame\"] == r[\"frames\"][-1][\"frame\"], r[\"interrupted\"]'"
done

# Memory: the plan's predicted peak against --max-memory, before any pixel is read.
check "a plan over --max-memory is refused with both figures, nothing written" bash -c "'$FP' run big.json -o mem --max-memory 1M > mem.log 2>&1; [ \$? = 2 ] && grep -q 'more than the 1.0 MiB allowed (--max-memory 1M)' mem.log && grep -q 'half resolution' mem.log && [ -z \"\$(ls mem 2>/dev/null | grep exr)\" ]"
check "--max-memory takes sizes as 8G, 512M" bash -c "'$FP' run one.json -o mem2 --max-memory 8G > /dev/null 2>&1 && '$FP' run one.json -o mem3 --max-memory 12X 2>&1 | grep -q 'expected a size such as 8G'"

# Output folders that cannot be made or written: an error naming the path and the reason, before
# the first frame, from every command that writes.
check "run -o into /proc: exit 2, the folder and the reason" expect_exit 2 "-o /proc/nope: cannot create the folder: No such file or directory" "$FP" run one.json -o /proc/nope
check "capture -o into /proc" expect_exit 2 "cannot create the folder" "$FP" capture "$SRC/examples/cornell/scene.json" -o /proc/nope/c.exr --width 16 --height 16
check "sheet -o into /proc" expect_exit 2 "cannot create the folder" "$FP" sheet seq.0001.exr -o /proc/nope/s.png
check "compare --heatmap into /proc" expect_exit 2 "cannot create the folder" "$FP" compare seq.0001.exr seq.0001.exr --layer SceneColor --heatmap /proc/nope/h.exr
check "bench --html into /proc" expect_exit 2 "cannot create the folder" "$FP" bench one.json --runs 1 --html /proc/nope/b.html
# A write that fails says why: a file size limit (RLIMIT_FSIZE, SIGXFSZ ignored) makes every
# write past 2 KiB fail with EFBIG, as a full disk fails with ENOSPC. The frame's output fails
# first; the report's failure is said too, and neither hides the other.
check "a report that cannot be written gives the system's reason" bash -c "trap '' XFSZ; ulimit -f 2; '$FP' run one.json -o small --report small/report.json > fsize.log 2>&1; [ \$? = 1 ] && grep -q 'report.json: could not write .*File too large' fsize.log && grep -q 'ssgi.0001.exr: could not write .*File too large' fsize.log"

# No command writes over its inputs.
cp -r "$SRC/examples/cornell" scene_copy
check "run --report onto the capture is refused, exit 2, capture untouched" bash -c "cp seq.0001.exr keep.exr &&
    echo '{ \"version\": 1, \"capture\": \"seq.0001.exr\" }' > one.json && '$FP' run one.json -o o1 --report seq.0001.exr > r.log 2>&1; [ \$? = 2 ] && grep -q 'that is an input of this command' r.log && cmp keep.exr seq.0001.exr"
check "run --report onto the config is refused" expect_exit 2 "--report one.json: that is an input" "$FP" run one.json -o o2 --report one.json
check "run --report where no file can be made fails before any frame" bash -c "'$FP' run one.json -o o3 --report /proc/version > p.log 2>&1; [ \$? = 2 ] && grep -q -- '--report /proc/version: cannot create a file in /proc' p.log && test ! -e o3"
check "compare --heatmap onto an input is refused, the input untouched" bash -c "'$FP' compare seq.0001.exr keep.exr --layer SceneColor --heatmap seq.0001.exr > h.log 2>&1; [ \$? = 2 ] && cmp keep.exr seq.0001.exr"
check "capture -o onto the scene's geometry is refused" bash -c "cp scene_copy/cornell.obj obj.keep && '$FP' capture scene_copy/scene.json -o scene_copy/cornell.obj > c.log 2>&1; [ \$? = 2 ] && grep -q 'that is an input' c.log && cmp obj.keep scene_copy/cornell.obj"

finish
