#!/usr/bin/env bash
# GuiCommandLineTest: hapticbox-gui given a job on its command line that fails (a model or a
# session it cannot open, a bake that fails) says so on stderr, naming the file and the cause,
# prints no VTK error text or pipeline dump, writes no screenshot and exits non-zero.
# Usage: gui_command_line_failures.sh HAPTICBOX_GUI CASE   (needs a display: xvfb-run -a ctest -L gui)
set -u
gui=$1
case_name=$2
d=$(mktemp -d)
trap 'rm -rf "$d"' EXIT
# The window's preferences and box cache in the temporary folder, never the user's.
export HOME=$d XDG_CONFIG_HOME=$d/config XDG_CACHE_HOME=$d/cache
printf 'OFF\n4 4 0\n0 0 0\n10 0 0\n0 10 0\n0 0 10\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' > "$d/tet.off"
case $case_name in
  MissingModel)
    file=$d/nowhere.nii.gz; want='nowhere.nii.gz'; cause='(No such|does not exist|cannot|not found)' ;;
  BrokenModel)
    printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n' > "$d/broken.off"
    file=$d/broken.off; want='broken.off'; cause='broken.off.*[:(].*[a-z]' ;;
  GarbageSession)
    printf '{ not json' > "$d/garbage.hbsession"
    file=$d/garbage.hbsession; want='garbage.hbsession'; cause='not a valid session file' ;;
  SessionWithoutItsModel)
    printf '{"format":"hapticbox-session","version":1,"mesh":"gone.off","bake":{"recipe":"default"}}' > "$d/lost.hbsession"
    file=$d/lost.hbsession; want='lost.hbsession'; cause='gone.off' ;;
  SessionNamingItself)
    # The window opened the session from the session until its stack overflowed (exit 139).
    printf '{"format":"hapticbox-session","version":1,"mesh":"self.hbsession","bake":{"recipe":"default"}}' > "$d/self.hbsession"
    file=$d/self.hbsession; want='self.hbsession'; cause='names this session file itself' ;;
  SessionCycle)
    printf '{"format":"hapticbox-session","version":1,"mesh":"b.hbsession","bake":{"recipe":"default"}}' > "$d/a.hbsession"
    printf '{"format":"hapticbox-session","version":1,"mesh":"a.hbsession","bake":{"recipe":"default"}}' > "$d/b.hbsession"
    file=$d/a.hbsession; want='a.hbsession'; cause='names the session file .*b.hbsession' ;;
  BakeThatFails)
    printf '{"format":"hapticbox-session","version":1,"mesh":"tet.off","bake":{"recipe":"advanced","m":8,"n":4,"pieces":"file","pieces_file":"gone_pieces.txt","baked":true}}' > "$d/bake.hbsession"
    file=$d/bake.hbsession; want='Bake of .*tet.off failed'; cause='gone_pieces.txt' ;;
  *) echo "unknown case $case_name"; exit 2 ;;
esac
out=$(timeout 300 "$gui" "$file" --screenshot "$d/shot.png" 2>&1 >/dev/null)
rc=$?
echo "exit $rc; stderr:"
echo "$out"
fail=0
[ $rc -ne 0 ] || { echo "FAIL: exit 0"; fail=1; }
[ $rc -ne 124 ] || { echo "FAIL: timed out"; fail=1; }
[ $rc -lt 128 ] || { echo "FAIL: died of a signal"; fail=1; }
grep -qE "^hapticbox-gui: .*$want" <<< "$out" || { echo "FAIL: no message naming $want"; fail=1; }
grep -qiE "$cause" <<< "$out" || { echo "FAIL: no cause ($cause)"; fail=1; }
if grep -qE 'ERROR: In |vtkExecutive|vtkCompositeDataPipeline|Algorithm vtk|Debug: Off' <<< "$out"; then
  echo "FAIL: VTK's error text or pipeline dump on stderr"; fail=1
fi
[ ! -e "$d/shot.png" ] || { echo "FAIL: a screenshot was written"; fail=1; }
exit $fail
