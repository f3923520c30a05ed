# The plant day's sensor data (tests/fault/plant_day.sh): one sensor-ingest JSON block per row of the IMS test-2
# feature table (984 snapshots), as a DAQ on the machine would publish it to MQTT. Each block is one snapshot:
# `rows` samples x 4 bearings at 20 kHz, stamped with the file's time, end_of_segment set (one snapshot = one
# segment, as sensor-replay numbers IMS files). The samples are seeded uniform noise of the row's mean |x| per
# bearing (mean |u| of U(-2a, 2a) is a), so the run degrades as IMS test 2 did; values are quantised to 0.001.
# The last row is written as the stopped machine the real last file is: every value on the ADC floor
# {-0.005, -0.002, 0, 0.002}.
#   awk -F, -v group=G -v rows=256 -v seed=24 -f plant_day_blocks.awk derived_per_file_stats_all984.csv
NR == 1 {
  for (i = 1; i <= NF; ++i) col[$i] = i
  srand(seed)
  next
}
{
  split($2, d, /[- :]/)
  t0 = sprintf("%d%09d", mktime_utc(d[1], d[2], d[3], d[4], d[5], d[6]), 0)
  stopped = (NR == last)
  line = sprintf("{\"asset_group\":\"%s\",\"channels\":[\"bearing1\",\"bearing2\",\"bearing3\",\"bearing4\"]," \
                 "\"sample_rate_hz\":20000,\"t0_ns\":%s,\"sequence\":%d,\"unit\":\"g\",\"end_of_segment\":true," \
                 "\"samples\":[", group, t0, NR - 2)
  for (r = 0; r < rows; ++r) {
    line = line (r ? "," : "") "["
    for (b = 1; b <= 4; ++b) {
      if (stopped) v = floor_value[int(rand() * 4)]
      else v = 2 * $(col["bearing" b "_meanabs"]) * (2 * rand() - 1)
      line = line (b > 1 ? "," : "") sprintf("%.3f", v)
    }
    line = line "]"
  }
  print line "]}"
}
BEGIN {
  floor_value[0] = -0.005; floor_value[1] = -0.002; floor_value[2] = 0; floor_value[3] = 0.002
  cmd = "wc -l < \"" ARGV[1] "\""; cmd | getline last; close(cmd)  # the header is line 1, so the last data row is line `last`
}
# Seconds since 1970-01-01 UTC without gawk's mktime (mawk has none): days from the civil date.
function mktime_utc(y, m, d, H, M, S,   a, yy, mm, days) {
  a = int((14 - m) / 12); yy = y + 4800 - a; mm = m + 12 * a - 3
  days = d + int((153 * mm + 2) / 5) + 365 * yy + int(yy / 4) - int(yy / 100) + int(yy / 400) - 32045 - 2440588
  return days * 86400 + H * 3600 + M * 60 + S
}
