// `hapticbox servo BOX --device virtual|replay:LOG|falcon --seconds S [--record LOG] [--json]
//  [--exact MESH [--render box|exact]] [--csv FILE] [--law penalty|proxy]`:
// runs the servo loop over a box file (or the built-in analytic scene `plane`) and prints the
// timing histogram and the safety events. --law chooses how answers become forces (the
// penalty law, or a god-object proxy kept by the loop: ServoOptions::contact_law); with
// --exact both answers are rendered by it, each with its own proxy. With --exact, the exact Embree answer on MESH runs
// in the same loop: one of the two drives the device (--render, box by default), the other is
// computed in shadow on the same segment in the same tick; the summary compares them (query
// times, contact agreement, force difference) and --record / --csv log both per tick.
#include "cli_support.h"
#include "perceptible_text.h"
#include "commands.h"
#include "tool_options.h"
#include "device/device_choice.h"
#include "device/plane_scene.h"
#include "device/servo_log.h"
#include "device/servo_loop.h"
#include "device/virtual_device.h"
#include "errors.h"
#include "exact/exact_query.h"
#include "figure_text.h"
#include "store/box_file.h"
#include "mesh/file_hash.h"
#ifdef HB_WITH_VTK
#include "trajectory_export.h"
#endif
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <thread>

namespace {

struct ServoArgs {
  std::string box;
  std::string device = "virtual";
  double seconds = 5.0;
  std::string record;
  std::string trajectory;  // .vtp polyline of the run (needs the VTK build)
  bool json = false;
  double rate_hz = 1000.0;
  bool no_realtime = false;
  double spin_us = 50.0;
  bool no_prime = false;
  hb::cli::WorkspaceArgs workspace;  // the scale and stiffness (the same as eval's for this model)
  std::string firmware;
  std::string exact;             // the mesh for the exact answer (empty: none)
  std::string render = "box";    // which answer drives the device with --exact
  std::string csv;
  std::string law = "penalty";   // the contact law: penalty | proxy (hb::contact_law)
  std::string route = "auto";   // the box scene's route (hb::SceneRoute)
  std::string tool;              // a tool with volume (empty: the point probe)
};

struct Scene {
  std::unique_ptr<hb::BoxScene> box;  // the box file's scene (null for `plane`)
  std::unique_ptr<hb::ContactQuery> query;
  hb::Vec3 min{hb::Vec3::Constant(-40.f)}, max{hb::Vec3::Constant(40.f)};  // the plane's model (mm)
  std::uint64_t mesh_hash = 0;  // of the mesh the box was baked from (0: unknown)
};

Scene load_scene(const std::string& box, const std::string& route) {
  Scene s;
  if (box == "plane") {
    s.query = std::make_unique<hb::PlaneScene>(0.f);  // 80 mm cube around the plane z = 0
    return s;
  }
  auto scene = std::make_unique<hb::BoxScene>(hb::load_box_file(box));
  if (scene->parts().boxes.empty()) throw hb::InvalidInput(box + ": the box file holds no boxes");
  s.mesh_hash = scene->parts().source.mesh_hash;
  hb::cli::apply_route(*scene, route);
  // The servo thread is one probe: its query state starts each tick from the last tick's
  // contact (BoxScene::query with a SceneQueryState; the stateless answers, tested).
  s.box = std::move(scene);
  s.query = std::make_unique<hb::SceneProbe>(*s.box);
  return s;
}

// The exact answer for --exact: the mesh (kept alive with its Embree scene).
struct ExactScene {
  hb::TriangleMesh mesh;
  std::unique_ptr<hb::ExactQuery> query;
};

std::unique_ptr<ExactScene> load_exact(const ServoArgs& a, const Scene& box) {
  if (a.exact.empty()) return nullptr;
  if (a.box == "plane") throw hb::cli::UsageError("--exact compares a box file with its mesh, not the plane scene");
  auto e = std::make_unique<ExactScene>();
  e->mesh = hb::cli::load_mesh(a.exact);
  if (box.mesh_hash != 0 && box.mesh_hash != hb::hash_model(a.exact))
    std::cerr << "hapticbox: warning: " << a.box << " was baked from a different file than " << a.exact << "\n";
  e->query = std::make_unique<hb::ExactQuery>(e->mesh);
  return e;
}

hb::OpenedDevice open_chosen_device(const ServoArgs& a, double dt) {
  hb::DeviceChoice choice;
  try {
    choice = hb::parse_device_choice(a.device);
  } catch (const hb::InvalidInput& e) {
    throw CLI::ValidationError("--device", e.what());
  }
  choice.falcon_firmware = a.firmware;
  hb::DeviceOpenOptions open;
  open.virtual_trajectory = hb::circle_probe_trajectory(0.02f, 0.01f, 4.0);
  open.dt_s = dt;
  open.on_hotplug = [](bool arrived, int bus, int address) {
    std::cerr << "hotplug: Falcon " << (arrived ? "plugged in" : "unplugged") << " (bus " << bus << " address "
              << address << ")\n";
  };
  return hb::open_device(choice, open);
}

void print_stats(const char* name, const hb::TimingStats& s) {
  std::printf("  %-9s p50 %9.2f us  p99 %9.2f us  p99.9 %9.2f us  max %9.2f us\n", name, s.p50_us,
              s.p99_us, s.p999_us, s.max_us);
}

// The loop's drive/shadow comparison told as box and exact.
struct BoxVsExact {
  bool box_drives;
  hb::TimingStats box_query, exact_query;
  std::uint64_t box_only, exact_only;
};

BoxVsExact box_vs_exact(const ServoArgs& a, const hb::ServoReport& r) {
  const hb::ShadowReport& sh = r.shadow;
  const bool box_drives = a.render == "box";
  return {box_drives, box_drives ? r.query : sh.query, box_drives ? sh.query : r.query,
          box_drives ? sh.drive_only : sh.shadow_only, box_drives ? sh.shadow_only : sh.drive_only};
}

void print_shadow(const ServoArgs& a, const hb::ServoReport& r) {
  const hb::ShadowReport& sh = r.shadow;
  const BoxVsExact c = box_vs_exact(a, r);
  std::printf("  box vs exact (%s drives the device, %s in shadow, same segment and %s law every tick):\n",
              c.box_drives ? "box" : "exact", c.box_drives ? "exact" : "box", hb::to_string(r.contact_law));
  print_stats("box", c.box_query);
  print_stats("exact", c.exact_query);
  std::printf("  query time exact / box: p50 %.2fx, p99 %.2fx\n",
              c.box_query.p50_us > 0 ? c.exact_query.p50_us / c.box_query.p50_us : 0.0,
              c.box_query.p99_us > 0 ? c.exact_query.p99_us / c.box_query.p99_us : 0.0);
  std::printf("  contact ticks: both %llu, box only %llu, exact only %llu, neither %llu\n",
              static_cast<unsigned long long>(sh.both_contact), static_cast<unsigned long long>(c.box_only),
              static_cast<unsigned long long>(c.exact_only), static_cast<unsigned long long>(sh.neither));
  std::printf("  |F_box - F_exact| (ticks with a contact): mean %.4f N, p50 %.4f N, p99 %.4f N, max %.4f N\n",
              sh.force_diff_mean_n, sh.force_diff_p50_n, sh.force_diff_p99_n, sh.force_diff_max_n);
  std::printf("  force direction difference (both in contact): p50 %.2f deg, p99 %.2f deg, max %.2f deg\n",
              sh.angle_p50_deg, sh.angle_p99_deg, sh.angle_max_deg);
  std::printf("  perceptibly different: %llu of %llu contact ticks (%s; %s)\n",
              static_cast<unsigned long long>(sh.perceptible), static_cast<unsigned long long>(sh.contact_ticks),
              hb::percent(sh.contact_ticks ? double(sh.perceptible) / double(sh.contact_ticks) : 0.0).c_str(),
              hb::thresholds_text(a.workspace.judge().thresholds).c_str());
}

nlohmann::json shadow_json(const ServoArgs& a, const hb::ServoReport& r) {
  const hb::ShadowReport& sh = r.shadow;
  const BoxVsExact c = box_vs_exact(a, r);
  return {{"rendered", a.render},
          {"mesh", a.exact},
          {"contact_law", hb::to_string(r.contact_law)},
          {"box_query_p50_us", c.box_query.p50_us},
          {"box_query_p99_us", c.box_query.p99_us},
          {"exact_query_p50_us", c.exact_query.p50_us},
          {"exact_query_p99_us", c.exact_query.p99_us},
          {"contact_both", sh.both_contact},
          {"contact_box_only", c.box_only},
          {"contact_exact_only", c.exact_only},
          {"contact_neither", sh.neither},
          {"force_diff_mean_n", sh.force_diff_mean_n},
          {"force_diff_p50_n", sh.force_diff_p50_n},
          {"force_diff_p99_n", sh.force_diff_p99_n},
          {"force_diff_max_n", sh.force_diff_max_n},
          {"angle_p50_deg", sh.angle_p50_deg},
          {"angle_p99_deg", sh.angle_p99_deg},
          {"angle_max_deg", sh.angle_max_deg},
          {"perceptible_ticks", sh.perceptible},
          {"contact_ticks", sh.contact_ticks},
          {"perceptible_share", sh.contact_ticks ? double(sh.perceptible) / double(sh.contact_ticks) : 0.0}};
}

void add_tool_json(nlohmann::json& j, const hb::ToolShape& tool, const hb::ServoReport& r) {
  j["tool"] = tool.spec;
  j["tool_points"] = tool.size();
  j["tool_max_torque_nm"] = r.tool_max_torque_nm;
  j["tool_max_substeps"] = r.tool_max_substeps;
}

void print_tool(const hb::ToolShape& tool, const hb::ServoReport& r) {
  std::printf("  tool: %s; its virtual coupling renders the force (largest torque on the simulated tool %.3g N m, "
              "not rendered by a 3-DOF device; up to %d sub-steps a tick)\n",
              hb::describe_tool(tool).c_str(), r.tool_max_torque_nm, r.tool_max_substeps);
}

nlohmann::json proxy_json(const hb::GodObjectStats& p) {
  return {{"contact_ticks", p.contact_ticks}, {"queries", p.queries},   {"seeds", p.seeds},
          {"reseeds", p.reseeds},             {"fallbacks", p.fallbacks}, {"max_planes", p.max_planes}};
}

void print_proxy(const char* what, const hb::GodObjectStats& p) {
  std::printf("    %s: contact ticks %llu, queries %.2f a tick, episodes %llu, reseeds %llu, penalty fallbacks %llu, "
              "at most %llu planes\n",
              what, static_cast<unsigned long long>(p.contact_ticks),
              p.ticks ? static_cast<double>(p.queries + p.ticks) / static_cast<double>(p.ticks) : 0.0,
              static_cast<unsigned long long>(p.seeds), static_cast<unsigned long long>(p.reseeds),
              static_cast<unsigned long long>(p.fallbacks), static_cast<unsigned long long>(p.max_planes));
}

// One scale for every command and the window: the box file's model (its mesh's diagonal,
// centred on its boxes) at the workspace's size and stiffness (hb::scene_workspace).
hb::Workspace scene_workspace(const ServoArgs& a, const Scene& scene) {
  if (scene.box) return hb::scene_workspace(*scene.box, a.workspace.options());
  hb::Bounds plane;
  plane.min = scene.min;
  plane.max = scene.max;
  return hb::make_workspace(plane, a.workspace.options());
}

// The loop's options from the command line.
hb::ServoOptions servo_options(const ServoArgs& a, const hb::Workspace& ws, double replay_rate_hz) {
  hb::ServoOptions o;
  o.rate_hz = a.rate_hz;
  o.request_realtime = !a.no_realtime;
  o.spin_s = a.spin_us * 1e-6;
  o.prime = !a.no_prime;
  o.workspace = ws;
  o.perceptual = a.workspace.judge().thresholds;
  o.shadow_is_reference = a.render != "exact";  // the JND is taken of exact's force
  o.contact_law = hb::contact_law(a.law);  // checked by the option already
  if (replay_rate_hz > 0) o.rate_hz = replay_rate_hz;  // a replay: same dt, same safety ramps, same forces
  if (!a.tool.empty()) o.tool = std::make_shared<const hb::ToolShape>(hb::cli::load_tool(a.tool));
  return o;
}

void run_servo(const ServoArgs& a) {
  if (a.render == "exact" && a.exact.empty()) throw hb::cli::UsageError("--render exact needs --exact MESH");
  Scene scene = load_scene(a.box, a.route);
  const std::unique_ptr<ExactScene> exact = load_exact(a, scene);
  const hb::ContactQuery* drive = scene.query.get();
  const hb::ContactQuery* shadow = nullptr;
  if (exact) {
    drive = a.render == "exact" ? static_cast<const hb::ContactQuery*>(exact->query.get()) : scene.query.get();
    shadow = a.render == "exact" ? scene.query.get() : static_cast<const hb::ContactQuery*>(exact->query.get());
  }
  hb::OpenedDevice opened = open_chosen_device(a, 1.0 / a.rate_hz);
  hb::HapticDevice* device = opened.device.get();
  const hb::Workspace ws = scene_workspace(a, scene);
  const hb::ServoOptions o = servo_options(a, ws, opened.rate_hz);

  std::unique_ptr<hb::LogRecorder> recorder;
  // --trajectory without --record records into a temporary log beside the .vtp.
  const std::string log_path = !a.record.empty() ? a.record : a.trajectory.empty() ? "" : a.trajectory + ".hbslog.tmp";
  if (!log_path.empty()) {
    if (exact)  // a comparison recording: both answers per tick
      recorder = std::make_unique<hb::LogRecorder>(
          log_path, o.rate_hz, device->spec(), a.render == "exact" ? hb::RenderedAnswer::exact : hb::RenderedAnswer::box);
    else
      recorder = std::make_unique<hb::LogRecorder>(log_path, o.rate_hz, device->spec());
  }

  hb::ServoLoop loop(*device, *drive, o);
  loop.set_recorder(recorder.get());
  loop.set_shadow(shadow);
  loop.start();
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(a.seconds);
  while (loop.running() && std::chrono::steady_clock::now() < until)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  loop.stop();
  if (recorder) recorder->finish();
  const hb::ServoReport& r = loop.report();
  std::size_t trajectory_points = 0;
#ifdef HB_WITH_VTK
  if (!a.trajectory.empty()) {
    const hb::ServoLog log = hb::read_servo_log(log_path);
    if (a.record.empty()) std::remove(log_path.c_str());
    trajectory_points = hb::cli::write_trajectory_vtp(log, o.workspace, a.box, a.trajectory);
  }
#endif
  if (!a.csv.empty()) hb::write_servo_log_csv(hb::read_servo_log(a.record), a.csv);

  if (a.json) {
    nlohmann::json j;
    j["device"] = device->spec().name;
    j["ticks"] = r.ticks;
    j["rate_hz"] = r.rate_hz;
    j["nominal_rate_hz"] = r.nominal_rate_hz;
    j["period_p50_us"] = r.period.p50_us;
    j["period_p99_us"] = r.period.p99_us;
    j["period_p999_us"] = r.period.p999_us;
    j["period_max_us"] = r.period.max_us;
    j["period_error_p99_us"] = r.period_error.p99_us;
    j["period_error_p999_us"] = r.period_error.p999_us;
    j["overruns"] = r.overruns;
    j["skipped"] = r.skipped;
    j["compute_p50_us"] = r.compute.p50_us;
    j["compute_p99_us"] = r.compute.p99_us;
    j["compute_max_us"] = r.compute.max_us;
    j["query_p99_us"] = r.query.p99_us;
    j["realtime_granted"] = r.realtime_granted;
    j["realtime_message"] = r.realtime_message;
    j["cache_priming"] = a.no_prime ? "off" : "on";
    j["stiffness_n_per_m"] = r.stiffness_n_per_m;
    j["stiffness_limited"] = r.stiffness_limited;
    j["workspace"] = hb::workspace_json(ws, a.workspace.judge());
    j["contact_law"] = o.tool ? "tool coupling" : hb::to_string(r.contact_law);
    if (o.tool) add_tool_json(j, *o.tool, r);
    if (scene.box) j["route"] = hb::route_name(scene.box->stroke_route());  // a probe with its query state
    if (r.contact_law == hb::ContactLaw::proxy) {
      j["proxy"] = proxy_json(r.proxy);
      if (exact) j["shadow_proxy"] = proxy_json(r.shadow_proxy);
    }
    for (std::size_t i = 0; i < hb::safety_event_count; ++i)
      j["safety_events"][hb::to_string(static_cast<hb::SafetyEvent>(i))] = r.safety[i];
    j["exit"] = hb::to_string(r.exit);
    j["exit_message"] = r.exit_message;
    if (!a.trajectory.empty()) {
      j["trajectory"] = a.trajectory;
      j["trajectory_points"] = trajectory_points;
    }
    if (recorder && !a.record.empty()) {
      j["log"] = a.record;
      j["log_records"] = recorder->written();
      j["log_dropped"] = recorder->dropped();
    }
    if (!a.csv.empty()) j["csv"] = a.csv;
    if (exact) j["box_vs_exact"] = shadow_json(a, r);
    std::cout << j.dump(2) << "\n";
  } else {
    std::printf("servo: %s, scene %s%s%s, %.0f Hz nominal\n", device->spec().name.c_str(), a.box.c_str(),
                scene.box ? ", route " : "", scene.box ? hb::route_name(scene.box->stroke_route()) : "",
                r.nominal_rate_hz);
    std::printf("  ticks %llu, measured rate %.2f Hz, overruns %llu (skipped %llu)\n",
                static_cast<unsigned long long>(r.ticks), r.rate_hz,
                static_cast<unsigned long long>(r.overruns), static_cast<unsigned long long>(r.skipped));
    print_stats("period", r.period);
    print_stats("|error|", r.period_error);
    print_stats("compute", r.compute);
    print_stats("query", r.query);
    std::printf("  real-time: %s (%s)\n", r.realtime_granted ? "granted" : "not granted",
                r.realtime_message.c_str());
    std::printf("  cache priming: %s\n", a.no_prime ? "off (HB_MEASURE=no-prime)"
                                                      : "on (the last segment's query at the start of the busy-wait)");
    std::printf("  workspace: %s\n", ws.describe().c_str());
    std::printf("  stiffness %.1f N/m%s\n", r.stiffness_n_per_m,
                r.stiffness_limited ? " (limited to the device's maximum)" : "");
    if (o.tool) {
      print_tool(*o.tool, r);
    } else if (r.contact_law == hb::ContactLaw::proxy) {
      std::printf("  contact law: proxy (god-object kept by the loop%s)\n", exact ? ", one for each answer" : "");
      const bool box_drives = a.render != "exact";
      print_proxy(!exact ? "proxy" : box_drives ? "box proxy" : "exact proxy", r.proxy);
      if (exact) print_proxy(box_drives ? "exact proxy (shadow)" : "box proxy (shadow)", r.shadow_proxy);
    } else {
      std::printf("  contact law: penalty (the force law on each tick's answer)\n");
    }
    std::printf("  safety events:");
    for (std::size_t i = 0; i < hb::safety_event_count; ++i)
      std::printf(" %s %llu", hb::to_string(static_cast<hb::SafetyEvent>(i)),
                  static_cast<unsigned long long>(r.safety[i]));
    std::printf("\n  exit: %s\n", r.exit_message.c_str());
    if (exact) print_shadow(a, r);
    if (!a.trajectory.empty())
      std::printf("  trajectory: %s, %zu points (polyline, open in ParaView)\n", a.trajectory.c_str(), trajectory_points);
    if (recorder && !a.record.empty())
      std::printf("  log: %s, %llu records, %llu dropped%s\n", a.record.c_str(),
                  static_cast<unsigned long long>(recorder->written()),
                  static_cast<unsigned long long>(recorder->dropped()),
                  exact ? " (box and exact per tick)" : "");
    if (!a.csv.empty()) std::printf("  csv: %s\n", a.csv.c_str());
  }
  if (r.exit == hb::ServoExit::disconnected)
    throw hb::DeviceDisconnected(device->spec().name + ": " + r.exit_message);
}

} // namespace

void add_servo_command(CLI::App& app) {
  auto a = std::make_shared<ServoArgs>();
  CLI::App* cmd = app.add_subcommand("servo", "Run the haptic servo loop and report its timing");
  cmd->add_option("BOX", a->box, "Box file (.hbox), or `plane` for the built-in analytic scene")
      ->required();
  cmd->add_option("--device", a->device, "virtual | replay:LOG | falcon")->capture_default_str();
  cmd->add_option("--seconds", a->seconds, "Run time, s")->check(hb::cli::finite_range(1e-3, 1e6))->capture_default_str();
  cmd->add_option("--record", a->record, "Write a full-rate binary log here");
#ifdef HB_WITH_VTK
  cmd->add_option("--trajectory", a->trajectory, "Write the run's probe path as a polyline .vtp (ParaView)");
#endif
  cmd->add_flag("--json", a->json, "Print the report as JSON");
  cmd->add_option("--rate", a->rate_hz, "Servo rate, Hz")->check(hb::cli::finite_range(1.0, 20000.0))->capture_default_str();
  cmd->add_flag("--no-realtime", a->no_realtime, "Do not ask for SCHED_FIFO");
  hb::cli::add_workspace_options(*cmd, a->workspace);
  cmd->add_option("--firmware", a->firmware, "Falcon firmware file (supplied by you; not shipped)");
  cmd->add_option("--exact", a->exact,
                  "The mesh BOX was baked from: its exact Embree answer runs in the same loop on the same "
                  "segment every tick, compared with the box in the summary and logged by --record/--csv");
  cmd->add_option("--render", a->render, "With --exact: which answer drives the device (the other runs in shadow)")
      ->check(CLI::IsMember({"box", "exact"}))
      ->capture_default_str();
  cmd->add_option("--law", a->law,
                  "Contact law: penalty (the force law on each tick's answer) or proxy (a god-object kept by the "
                  "loop; with --exact, one for each answer)")
      ->check([](const std::string& v) {
        try {
          hb::contact_law(v);
          return std::string();
        } catch (const hb::InvalidInput& e) {
          return std::string(e.what());
        }
      })
      ->capture_default_str();
  hb::cli::add_route_option(*cmd, a->route);
  auto* record = cmd->get_option("--record");
  cmd->add_option("--tool", a->tool,
                  "A tool with volume at the device (sphere,radius-mm=R,points=N | capsule,radius-mm=R,length-mm=L,"
                  "points=N | mesh=FILE,points=N): its centre follows the device, a virtual coupling renders it");
  cmd->add_option("--csv", a->csv, "Also write the recorded log as CSV (one row a tick; box_* and exact_* "
                                   "columns with --exact)")
      ->needs(record);
  cmd->callback([a] {
    // Measurement-only (HB_MEASURE): spin-us=N, the busy-wait before each deadline; no-prime,
    // the busy-wait without querying the last segment (the caches as the sleep left them).
    if (const auto spin = hb::cli::measurement("spin-us"))
      a->spin_us = hb::cli::spec_number_or_usage(*spin, "HB_MEASURE spin-us", 0.0, 1000.0);
    a->no_prime = hb::cli::measurement("no-prime").has_value();
    if (!a->trajectory.empty() && hb::cli::lower_extension(a->trajectory) != ".vtp")
      throw hb::cli::UsageError("--trajectory " + a->trajectory + ": the trajectory is written as VTK XML PolyData; name it .vtp");
    run_servo(*a);
  });
}
