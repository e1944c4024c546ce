#include "runtime/recording_csv.hpp"

#include <charconv>
#include <string>
#include <string_view>

namespace tactus::runtime {

namespace {

void put(std::string& row, double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  row.append(buf, r.ptr);
}

template <class Int>
void put_int(std::string& row, Int v) {
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  row.append(buf, r.ptr);
}

/// RFC 4180: quoted when it holds a comma, quote or line break; quotes doubled.
void put_text(std::string& row, std::string_view s) {
  if (s.find_first_of(",\"\r\n") == std::string_view::npos) {
    row += s;
    return;
  }
  row += '"';
  for (const char c : s) {
    if (c == '"') row += '"';
    row += c;
  }
  row += '"';
}

void put_device(std::string& row, const RecordingHeader& header, std::uint16_t device) {
  if (device < header.devices.size())
    put_text(row, header.devices[device]);
  else
    put_int(row, device);
}

void put_xyz(std::string& row, const Vec3& v) {
  for (int k = 0; k < 3; ++k) {
    row += ',';
    put(row, v[k]);
  }
}

double microseconds(double ns) { return ns / 1000.0; }

}  // namespace

void write_frames_csv(const Recording& recording, std::ostream& out) {
  out << "t,device,frame,x,y,z,qw,qx,qy,qz,buttons,fx,fy,fz,tx,ty,tz,contact,flags,"
         "proxy_x,proxy_y,proxy_z,compute_us,late_us\n";
  std::string row;
  for (const HapticFrame& f : recording.frames) {
    row.clear();
    put(row, f.t);
    row += ',';
    put_device(row, recording.header, f.device);
    row += ',';
    put_int(row, f.frame);
    put_xyz(row, f.position);
    for (const double q : {f.orientation.w(), f.orientation.x(), f.orientation.y(), f.orientation.z()}) {
      row += ',';
      put(row, q);
    }
    row += ',';
    put_int(row, f.buttons);
    put_xyz(row, f.force);
    put_xyz(row, f.torque);
    row += ',';
    put_int(row, unsigned{f.contact});
    row += ',';
    put_int(row, unsigned{f.flags});
    put_xyz(row, f.proxy);
    row += ',';
    put(row, microseconds(f.compute_ns));
    row += ',';
    put(row, microseconds(f.late_ns));
    row += '\n';
    out << row;
  }
}

void write_steps_csv(const Recording& recording, std::ostream& out) {
  out << "t,step,compute_us,solver_iterations,late_us\n";
  std::string row;
  for (const SimulationStep& s : recording.steps) {
    row.clear();
    put(row, s.t);
    row += ',';
    put_int(row, s.step);
    row += ',';
    put(row, microseconds(s.compute_ns));
    row += ',';
    put_int(row, s.solver_iterations);
    row += ',';
    put(row, microseconds(s.late_ns));
    row += '\n';
    out << row;
  }
}

void write_events_csv(const Recording& recording, std::ostream& out) {
  out << "t,kind,device,value,text\n";
  std::string row;
  for (const Event& e : recording.events) {
    row.clear();
    put(row, e.t);
    row += ',';
    row += event_kind_name(e.kind);
    row += ',';
    put_device(row, recording.header, e.device);
    row += ',';
    put(row, e.value);
    row += ',';
    put_text(row, e.text);
    row += '\n';
    out << row;
  }
}

}  // namespace tactus::runtime
