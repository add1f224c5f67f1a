#include "batch/report/svg_canvas.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "render/image_io.h"

namespace tavis::batch::report {
namespace {

// The canvas is drawn in RGB order (what EncodePng takes), not OpenCV's usual BGR.
cv::Scalar Rgb(const std::string& colour) {
  unsigned r = 0, g = 0, b = 0;
  if (colour.size() != 7 || std::sscanf(colour.c_str(), "#%02x%02x%02x", &r, &g, &b) != 3) {
    throw std::invalid_argument("colour must be #rrggbb, got '" + colour + "'");
  }
  return cv::Scalar(r, g, b);
}

std::string DataText(const DataAttributes& data) {
  std::string text;
  for (const auto& [name, value] : data) text += " data-" + name + "=\"" + EscapeXml(value) + "\"";
  return text;
}

// Fixed-point pixel coordinates for OpenCV's anti-aliased drawing (4 fractional bits).
constexpr int kShift = 4;
cv::Point Px(double x, double y) {
  return {static_cast<int>(std::lround(x * 16)), static_cast<int>(std::lround(y * 16))};
}

// The PNG is drawn at twice the size and halved, for smoother lines and text.
constexpr double kPngScale = 2.0;
// Hershey simplex is about 22 px tall at scale 1.
double HersheyScale(double size) { return size * kPngScale / 22.0; }

}  // namespace

double Canvas::TextWidth(const std::string& text, double size) {
  int baseline = 0;
  const cv::Size hershey = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, HersheyScale(size), 1, &baseline);
  // The PNG's Hershey glyphs are wider than a browser's sans-serif: the larger of the two.
  return std::max(hershey.width / kPngScale, 0.6 * size * static_cast<double>(text.size()));
}

std::string EscapeXml(const std::string& text) {
  std::string escaped;
  for (const char c : text) {
    switch (c) {
      case '&': escaped += "&amp;"; break;
      case '<': escaped += "&lt;"; break;
      case '>': escaped += "&gt;"; break;
      case '"': escaped += "&quot;"; break;
      default: escaped += c;
    }
  }
  return escaped;
}

std::string Num(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.6g", value);
  return text;
}

Canvas::Canvas(int width, int height) : width_(width), height_(height) {}

void Canvas::Line(double x1, double y1, double x2, double y2, const std::string& colour, double stroke_width,
                  bool dashed, DataAttributes data) {
  Mark mark;
  mark.kind = Mark::Kind::kLine;
  mark.a = x1, mark.b = y1, mark.c = x2, mark.d = y2;
  mark.colour = colour;
  mark.stroke_width = stroke_width;
  mark.dashed = dashed;
  mark.data = std::move(data);
  marks_.push_back(std::move(mark));
}

void Canvas::Rect(double x, double y, double w, double h, const std::string& fill, double fill_opacity,
                  const std::string& stroke, DataAttributes data) {
  Mark mark;
  mark.kind = Mark::Kind::kRect;
  mark.a = x, mark.b = y, mark.c = w, mark.d = h;
  mark.colour = fill;
  mark.opacity = fill_opacity;
  mark.stroke = stroke;
  mark.data = std::move(data);
  marks_.push_back(std::move(mark));
}

void Canvas::Circle(double cx, double cy, double r, const std::string& colour, bool filled, DataAttributes data) {
  Mark mark;
  mark.kind = Mark::Kind::kCircle;
  mark.a = cx, mark.b = cy, mark.c = r;
  mark.colour = colour;
  mark.filled = filled;
  mark.data = std::move(data);
  marks_.push_back(std::move(mark));
}

void Canvas::Text(double x, double y, const std::string& text, double size, Anchor anchor, const std::string& colour) {
  Mark mark;
  mark.kind = Mark::Kind::kText;
  mark.a = x, mark.b = y, mark.c = size;
  mark.text = text;
  mark.anchor = anchor;
  mark.colour = colour;
  marks_.push_back(std::move(mark));
}

std::string Canvas::Svg(const std::string& id) const {
  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" id=\"" << EscapeXml(id) << "\" width=\"" << width_ << "\" height=\""
      << height_ << "\" viewBox=\"0 0 " << width_ << " " << height_ << "\" font-family=\"sans-serif\">\n<rect width=\""
      << width_ << "\" height=\"" << height_ << "\" fill=\"#ffffff\"/>\n";
  for (const Mark& mark : marks_) {
    switch (mark.kind) {
      case Mark::Kind::kLine:
        svg << "<line x1=\"" << Num(mark.a) << "\" y1=\"" << Num(mark.b) << "\" x2=\"" << Num(mark.c) << "\" y2=\""
            << Num(mark.d) << "\" stroke=\"" << mark.colour << "\" stroke-width=\"" << Num(mark.stroke_width) << "\""
            << (mark.dashed ? " stroke-dasharray=\"4,3\"" : "") << DataText(mark.data) << "/>\n";
        break;
      case Mark::Kind::kRect:
        svg << "<rect x=\"" << Num(mark.a) << "\" y=\"" << Num(mark.b) << "\" width=\"" << Num(mark.c) << "\" height=\""
            << Num(mark.d) << "\" fill=\"" << mark.colour << "\" fill-opacity=\"" << Num(mark.opacity) << "\" stroke=\""
            << (mark.stroke.empty() ? "none" : mark.stroke) << "\"" << DataText(mark.data) << "/>\n";
        break;
      case Mark::Kind::kCircle:
        svg << "<circle cx=\"" << Num(mark.a) << "\" cy=\"" << Num(mark.b) << "\" r=\"" << Num(mark.c) << "\" stroke=\""
            << mark.colour << "\" fill=\"" << (mark.filled ? mark.colour : "#ffffff") << "\"" << DataText(mark.data)
            << "/>\n";
        break;
      case Mark::Kind::kText: {
        const char* anchor = mark.anchor == Anchor::kStart    ? "start"
                             : mark.anchor == Anchor::kMiddle ? "middle"
                                                              : "end";
        svg << "<text x=\"" << Num(mark.a) << "\" y=\"" << Num(mark.b) << "\" font-size=\"" << Num(mark.c)
            << "\" text-anchor=\"" << anchor << "\" fill=\"" << mark.colour << "\">" << EscapeXml(mark.text)
            << "</text>\n";
        break;
      }
    }
  }
  svg << "</svg>\n";
  return svg.str();
}

std::string Canvas::Png() const {
  constexpr double kScale = kPngScale;
  cv::Mat image(static_cast<int>(height_ * kScale), static_cast<int>(width_ * kScale), CV_8UC3,
                cv::Scalar(255, 255, 255));
  for (const Mark& mark : marks_) {
    switch (mark.kind) {
      case Mark::Kind::kLine: {
        const int thickness = std::max(1, static_cast<int>(std::lround(mark.stroke_width * kScale)));
        if (!mark.dashed) {
          cv::line(image, Px(mark.a * kScale, mark.b * kScale), Px(mark.c * kScale, mark.d * kScale), Rgb(mark.colour),
                   thickness, cv::LINE_AA, kShift);
          break;
        }
        const double length = std::hypot(mark.c - mark.a, mark.d - mark.b);
        for (double s = 0.0; s < length; s += 7.0) {  // 4 on, 3 off, as the SVG's dasharray
          const double e = std::min(length, s + 4.0);
          const auto at = [&](double t) {
            return Px((mark.a + (mark.c - mark.a) * t / length) * kScale,
                      (mark.b + (mark.d - mark.b) * t / length) * kScale);
          };
          cv::line(image, at(s), at(e), Rgb(mark.colour), thickness, cv::LINE_AA, kShift);
        }
        break;
      }
      case Mark::Kind::kRect: {
        const cv::Rect box(
            static_cast<int>(std::lround(mark.a * kScale)), static_cast<int>(std::lround(mark.b * kScale)),
            static_cast<int>(std::lround(mark.c * kScale)), static_cast<int>(std::lround(mark.d * kScale)));
        const cv::Rect clipped = box & cv::Rect(0, 0, image.cols, image.rows);
        if (clipped.area() > 0) {
          cv::Mat region = image(clipped);
          cv::Mat fill(region.size(), region.type(), Rgb(mark.colour));
          cv::addWeighted(fill, mark.opacity, region, 1.0 - mark.opacity, 0.0, region);
        }
        if (!mark.stroke.empty()) cv::rectangle(image, box, Rgb(mark.stroke), static_cast<int>(kScale), cv::LINE_AA);
        break;
      }
      case Mark::Kind::kCircle:
        if (!mark.filled)
          cv::circle(image, Px(mark.a * kScale, mark.b * kScale), static_cast<int>(mark.c * kScale * 16),
                     cv::Scalar(255, 255, 255), cv::FILLED, cv::LINE_AA, kShift);
        cv::circle(image, Px(mark.a * kScale, mark.b * kScale), static_cast<int>(mark.c * kScale * 16),
                   Rgb(mark.colour), mark.filled ? cv::FILLED : static_cast<int>(kScale), cv::LINE_AA, kShift);
        break;
      case Mark::Kind::kText: {
        const double font_scale = HersheyScale(mark.c);
        int baseline = 0;
        const cv::Size size = cv::getTextSize(mark.text, cv::FONT_HERSHEY_SIMPLEX, font_scale, 1, &baseline);
        double x = mark.a * kScale;
        if (mark.anchor == Anchor::kMiddle) x -= size.width / 2.0;
        if (mark.anchor == Anchor::kEnd) x -= size.width;
        cv::putText(image, mark.text, cv::Point(static_cast<int>(x), static_cast<int>(mark.b * kScale)),
                    cv::FONT_HERSHEY_SIMPLEX, font_scale, Rgb(mark.colour), 1, cv::LINE_AA);
        break;
      }
    }
  }
  cv::Mat half;
  cv::resize(image, half, cv::Size(width_, height_), 0, 0, cv::INTER_AREA);
  return render::EncodePng(half.rows, half.cols, half.data);
}

}  // namespace tavis::batch::report
