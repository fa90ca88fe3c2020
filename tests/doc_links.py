"""The documentation's links and size.

Every relative Markdown link X.md#anchor (and #anchor within a page) of README.md, docs/*.md and
every folder's README.md must resolve to a heading (GitHub-style anchors) or an explicit
<a id="..."> of the target file, and linked files must exist. README.md stays a page a newcomer
reads in five minutes (at most 200 lines) and docs/performance.md a page of current figures (at
most 500 lines): measurements that superseded ones replace them, and how a number evolved goes in
commit messages, not in the docs.
Usage: doc_links.py [REPOSITORY_ROOT]"""
import glob, os, re, sys
root = sys.argv[1] if len(sys.argv) > 1 else '.'
files = [os.path.join(root, 'README.md')] + sorted(glob.glob(os.path.join(root, 'docs', '*.md')))
files += sorted(f for f in glob.glob(os.path.join(root, '**', 'README.md'), recursive=True)
                if '/build' not in f and '/.git' not in f and f not in files)
def slug(h):
    h = h.strip().lower()
    h = re.sub(r'[^\w\- ]', '', h)   # drop punctuation (keeps letters, digits, _, -, space)
    return h.replace(' ', '-')
anchors = {}
def anchors_of(path):
    if path not in anchors:
        a, seen, in_code = set(), {}, False
        for line in open(path):
            if line.startswith('```'):
                in_code = not in_code
            if in_code:
                continue
            m = re.match(r'^(#{1,6})\s+(.*?)\s*#*\s*$', line)
            if m:
                s = slug(m.group(2))
                n = seen.get(s, 0); seen[s] = n + 1
                a.add(s if n == 0 else f'{s}-{n}')
            for m in re.finditer(r'<a (?:id|name)="([^"]+)"', line):
                a.add(m.group(1))
        anchors[path] = a
    return anchors[path]
bad = 0; count = 0
for f in files:
    text = open(f).read()
    text = re.sub(r'```.*?```', '', text, flags=re.S)
    for m in re.finditer(r'\]\(([^)\s]+)\)', text):
        target = m.group(1)
        if re.match(r'^[a-z]+:', target):
            continue
        path, _, anchor = target.partition('#')
        dest = os.path.normpath(os.path.join(os.path.dirname(f), path)) if path else f
        count += 1
        if not os.path.exists(dest):
            print(f'{f}: missing file {target}'); bad += 1; continue
        if anchor and dest.endswith('.md') and anchor not in anchors_of(dest):
            print(f'{f}: no anchor #{anchor} in {dest}'); bad += 1
for name, limit in (('README.md', 200), (os.path.join('docs', 'performance.md'), 500)):
    lines = sum(1 for _ in open(os.path.join(root, name)))
    if lines > limit:
        print(f'{name}: {lines} lines, more than {limit}'); bad += 1
print(f'{count} links checked in {len(files)} files, {bad} bad')
sys.exit(1 if bad else 0)
