// Uses the installed secchi::exr target: an image through OpenEXR and back.
#include <secchi/io/exr.hpp>
#include <cstdio>

int main() {
    secchi::Image image(3, 2);
    image.add_channel("L")[4] = 0.25f;
    secchi::write_exr(image, "consumer.exr");
    const secchi::Image back = secchi::read_exr("consumer.exr");
    std::printf("L[4] %.2f\n", back.channel("L")[4]);
    return back.channel("L")[4] == 0.25f ? 0 : 1;
}
