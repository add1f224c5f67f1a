// A small vector canvas for the report's figures: lines, rectangles, circles and text in pixel
// coordinates, written as standalone SVG (our own writer) and rasterised to PNG with OpenCV. Marks
// can carry data-* attributes (the numbers they show), so a test reads a figure's numbers back
// from its SVG.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace tavis::batch::report {

using DataAttributes = std::vector<std::pair<std::string, std::string>>;  // name (without data-) -> value

class Canvas {
 public:
  Canvas(int width, int height);

  int width() const { return width_; }
  int height() const { return height_; }

  // Colours are "#rrggbb".
  void Line(double x1, double y1, double x2, double y2, const std::string& colour, double stroke_width = 1.0,
            bool dashed = false, DataAttributes data = {});
  void Rect(double x, double y, double w, double h, const std::string& fill, double fill_opacity,
            const std::string& stroke, DataAttributes data = {});
  void Circle(double cx, double cy, double r, const std::string& colour, bool filled, DataAttributes data = {});
  enum class Anchor { kStart, kMiddle, kEnd };
  void Text(double x, double y, const std::string& text, double size = 11.0, Anchor anchor = Anchor::kStart,
            const std::string& colour = "#222222");

  // How wide `text` is drawn at `size` (px), in the PNG's font or a browser's sans-serif,
  // whichever is wider: what figure layouts reserve, so that labels neither overlap nor clip.
  static double TextWidth(const std::string& text, double size);

  // <svg> with a white background; `id` names it (for the HTML report and tests).
  std::string Svg(const std::string& id) const;
  // The same drawing as the bytes of an 8-bit RGB PNG file (rasterised with OpenCV, text in its
  // Hershey font; encoded by libpng).
  std::string Png() const;

 private:
  struct Mark {
    enum class Kind { kLine, kRect, kCircle, kText } kind = Kind::kLine;
    double a = 0, b = 0, c = 0, d = 0;  // line: x1 y1 x2 y2; rect: x y w h; circle: cx cy r; text: x y size
    std::string colour, stroke, text;
    double opacity = 1.0, stroke_width = 1.0;
    bool dashed = false, filled = true;
    Anchor anchor = Anchor::kStart;
    DataAttributes data;
  };
  int width_, height_;
  std::vector<Mark> marks_;
};

// Escapes &, <, >, " for HTML and SVG text and attributes.
std::string EscapeXml(const std::string& text);
// A number as the SVG and data attributes write it: up to 6 significant digits.
std::string Num(double value);

}  // namespace tavis::batch::report
