// Case-file keys of the Output section: history rows, snapshots, progress, checkpoints.
#include "case_keys.h"

namespace app::keys
{
  void declare_output_keys(Section &s, coupling::CaseParameters &p)
  {
    coupling::OutputParameters &o = p.output;
    s.add<int>("History rows", o.n_history_rows, "about this many rows in history.csv",
               [](int v) { return v >= 2 && v <= 10000000; }, "must be in [2, 10000000]");
    s.add<int>("Snapshots", o.n_snapshots, "particle / mesh snapshots in results.h5",
               [](int v) { return v >= 0 && v <= 100000; }, "must be in [0, 100000]");
    s.add("Progress", o.progress, "progress display on stderr (also --quiet)");
    s.add<int>("Checkpoint interval", o.checkpoint_steps, "write checkpoint.h5 every this many steps; 0 = not by steps",
               [](int v) { return v >= 0; }, "must be >= 0 steps (0 = no periodic checkpoints)");
    s.add<double>("Checkpoint minutes", o.checkpoint_minutes,
                  "write checkpoint.h5 every this many minutes of wall time; 0 = not by time",
                  [](double v) { return v >= 0 && v <= 1e6; }, "must be in [0, 1e6] minutes (0 = no timed checkpoints)");
    s.add<long>("Stop after steps", o.stop_after_steps,
                "stop with a checkpoint after this step, as on SIGTERM (restart tests); 0 = never",
                [](long v) { return v >= 0; }, "must be >= 0 (0 = never)");
  }
} // namespace app::keys
