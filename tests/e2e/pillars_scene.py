"""What the e2e tests know of tests/apps_extra/pillars.c's scene, and how they count what a pass
did to its floor."""

FLOOR = (90, 90, 90)  # the floor's colour, unlit


def floor_changes(plain, decorated, inside=None):
    """Of the floor's pixels of `plain` (an image as png.read_png gives it) for which
    inside(x, y, height) holds (all when None): how many, and how many `decorated` made whiter
    and darker (by more than 30 in the sum of their channels)."""
    w, h, a = plain
    b = decorated[2]
    floor = whiter = darker = 0
    for y in range(h):
        for x in range(w):
            if tuple(a[y][x][:3]) != FLOOR or (inside and not inside(x, y, h)):
                continue
            floor += 1
            delta = sum(b[y][x][:3]) - sum(a[y][x][:3])
            whiter += delta > 30
            darker += delta < -30
    return floor, whiter, darker
